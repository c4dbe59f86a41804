#pragma once
// Progress of a long run on stderr, with the time remaining: the one place every command that
// can take more than a few seconds reports it (reproduce, solver-suite, and new commands).
//
//   Progress progress("reproduce", total, "trials", progress_wanted(vm));
//   ... from any thread, after each item: progress.advance();
//   progress.finish();
//
// On a terminal one line is rewritten in place (at most 4 times a second); otherwise (only
// with --progress) a full line the first time and then at most every 2 seconds, so a log
// stays short. Disabled, it prints nothing: tests and pipes stay clean.

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace kincal::cli {

class Progress {
 public:
  Progress(std::string command, long total, std::string unit, bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Counts `n` more items done; thread-safe.
  void advance(long n = 1);
  /// Ends the line on a terminal; called by the destructor too.
  void finish();

  /// "12/500 trials, 3 s elapsed, about 2 min 4 s left": the line shown, for the tests.
  static std::string line(long done, long total, const std::string& unit, double elapsed_s);

 private:
  const std::string command_, unit_;
  const long total_;
  const bool enabled_, terminal_;
  const std::chrono::steady_clock::time_point start_;
  std::atomic<long> done_{0};
  std::mutex mutex_;
  double last_shown_ = -1;
  bool open_line_ = false;
};

/// "45 s", "2 min 4 s", "1 h 3 min".
std::string duration_text(double seconds);

}  // namespace kincal::cli
