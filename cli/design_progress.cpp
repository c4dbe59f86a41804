#include "kincal/cli/design_progress.hpp"

#include <algorithm>

#include "kincal/cli/interrupt.hpp"

namespace kincal::cli {

DesignMonitor DesignProgress::monitor() {
  return [this](const DesignStep& s) { return step(s); };
}

void DesignProgress::finish() {
  if (progress_) progress_->finish();
}

bool DesignProgress::step(const DesignStep& step) {
  const std::string name(step.stage);
  const std::string stage = step.pass ? name + " pass " + std::to_string(step.pass) : name;
  if (show_ && stage != stage_) {
    if (progress_) progress_->finish();
    const std::string unit = name == "candidates" ? "candidates drawn"
                             : name == "greedy"   ? "measurements picked (greedy start)"
                             : name == "bound"    ? "bound iterations (at most)"
                                                  : "measurements revisited (exchange pass " +
                                                     std::to_string(step.pass) + ")";
    // A stage shows after a second: quick designs stay quiet. The exchange's passes count
    // that second from the exchange's start, so a long exchange of short passes shows.
    const auto now = std::chrono::steady_clock::now();
    if (name == "exchange" && step.pass == 1) exchange_start_ = now;
    const double delay =
        name == "exchange"
            ? std::max(0.0, 1.0 - std::chrono::duration<double>(now - exchange_start_).count())
            : 1.0;
    progress_ = std::make_unique<Progress>("design", step.total, unit, true, delay);
    stage_ = stage;
    done_ = 0;
  }
  if (progress_ && step.done > done_) {
    progress_->advance(step.done - done_);
    done_ = step.done;
  }
  return !interrupt_requested();
}

}  // namespace kincal::cli
