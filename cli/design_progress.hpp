#pragma once
// `kincal design`'s progress on stderr, one line per stage (candidates, greedy start, each
// exchange pass, the bound) with its own count and time left, and its Ctrl-C: the monitor it
// gives the design workflow stops the work at the first interrupt (the best design so far,
// marked partial).

#include <chrono>
#include <memory>
#include <string>

#include "kincal/cli/progress.hpp"
#include "kincal/framework/design/experiment_design.hpp"

namespace kincal::cli {

class DesignProgress {
 public:
  explicit DesignProgress(bool show) : show_(show) {}
  /// The monitor for DesignOptions::monitor; `this` must outlive the design.
  DesignMonitor monitor();
  /// Ends the current stage's line.
  void finish();

 private:
  bool step(const DesignStep& step);

  bool show_;
  std::unique_ptr<Progress> progress_;
  std::string stage_;
  long done_ = 0;
  std::chrono::steady_clock::time_point exchange_start_;
};

}  // namespace kincal::cli
