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
#include <vector>

namespace kincal::cli {

class Progress {
 public:
  /// Nothing is shown before `delay_s` seconds have passed (a stage that ends sooner says
  /// nothing).
  Progress(std::string command, long total, std::string unit, bool enabled, double delay_s = 0);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Counts `n` more items done; thread-safe. The time left is the rate so far times the
  /// items left.
  void advance(long n = 1);
  /// The same with the caller's estimate of the time left, in seconds (NaN: none), for runs
  /// whose items cost different amounts in a way the caller can weigh (staged_time_left).
  void advance(long n, double seconds_left);
  /// Ends the line on a terminal; called by the destructor too.
  void finish();

  /// "12/500 trials, 3 s elapsed, about 2 min 4 s left": the line shown, for the tests.
  static std::string line(long done, long total, const std::string& unit, double elapsed_s);
  /// The same with an estimate of the time left (NaN: none); below half a second it reads
  /// "under 1 s left", never "0 s left" while items remain.
  static std::string line(long done, long total, const std::string& unit, double elapsed_s,
                          double seconds_left);

 private:
  const std::string command_, unit_;
  const long total_;
  const bool enabled_, terminal_;
  const double delay_s_;
  const std::chrono::steady_clock::time_point start_;
  std::atomic<long> done_{0};
  std::mutex mutex_;
  double last_shown_ = -1;
  bool open_line_ = false;
};

/// The time left of a run of `stages` stages (solver-suite's backends) of `per_stage` items
/// each (the same items in the same order in every stage), from the durations (s) of the
/// items done so far: durations[s][i], stages in order, the last one possibly under way.
/// Item i costs what the finished stages' item i cost on average (their profile), scaled by
/// its stage's factor: for the stage under way, its time so far over the profile's on the
/// same items; for the stages not started, the mean factor of the stages started. Before any
/// stage has finished, the stage under way's mean rate. NaN when nothing is done.
double staged_time_left(const std::vector<std::vector<double>>& durations, long per_stage,
                        int stages);

/// "45 s", "2 min 4 s", "1 h 3 min".
std::string duration_text(double seconds);

}  // namespace kincal::cli
