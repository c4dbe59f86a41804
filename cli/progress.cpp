#include "kincal/cli/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "kincal/cli/console.hpp"

namespace kincal::cli {

std::string duration_text(double seconds) {
  const long s = std::lround(std::max(seconds, 0.0));
  char text[48];
  if (s < 60)
    std::snprintf(text, sizeof text, "%ld s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%ld min %ld s", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld h %ld min", s / 3600, (s % 3600) / 60);
  return text;
}

std::string Progress::line(long done, long total, const std::string& unit, double elapsed_s) {
  // The rate so far predicts the rest; nothing to predict from before the first item.
  return line(
      done, total, unit, elapsed_s,
      done > 0 ? elapsed_s / done * (total - done) : std::numeric_limits<double>::quiet_NaN());
}

std::string Progress::line(long done, long total, const std::string& unit, double elapsed_s,
                           double seconds_left) {
  std::string text = std::to_string(done) + "/" + std::to_string(total) + " " + unit + ", " +
                     duration_text(elapsed_s) + " elapsed";
  if (done < total && std::isfinite(seconds_left))
    text += seconds_left < 0.5 ? std::string(", under 1 s left")
                               : ", about " + duration_text(seconds_left) + " left";
  return text;
}

double staged_time_left(const std::vector<std::vector<double>>& durations, long per_stage,
                        int stages) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int started = static_cast<int>(durations.size());
  if (started == 0 || per_stage <= 0) return nan;
  const std::vector<double>& current = durations.back();
  const long k = static_cast<long>(current.size());
  const bool current_finished = k >= per_stage;
  const int finished = started - (current_finished ? 0 : 1);
  const auto sum = [](const std::vector<double>& v, long from, long to) {
    double s = 0;
    for (long i = from; i < to && i < static_cast<long>(v.size()); ++i) s += v[i];
    return s;
  };
  if (finished == 0) {
    if (k == 0) return nan;
    const double rate = sum(current, 0, k) / k;
    return rate * (per_stage - k) + rate * per_stage * (stages - started);
  }
  std::vector<double> profile(per_stage, 0.0);
  for (int s = 0; s < finished; ++s)
    for (long i = 0; i < per_stage; ++i)
      profile[i] += (i < static_cast<long>(durations[s].size()) ? durations[s][i] : 0) / finished;
  const double whole = sum(profile, 0, per_stage);
  double left = 0, factors = finished;  // each finished stage's factor averages 1
  if (!current_finished) {
    const double seen = sum(profile, 0, k);
    const double factor = k > 0 && seen > 0 ? sum(current, 0, k) / seen : 1.0;
    left += factor * sum(profile, k, per_stage);
    factors += factor;
  }
  left += (stages - started) * whole * factors / started;
  return left;
}

Progress::Progress(std::string command, long total, std::string unit, bool enabled, double delay_s)
    : command_(std::move(command)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(enabled),
      terminal_(err_is_process_stderr() && ::isatty(STDERR_FILENO) != 0),
      delay_s_(delay_s),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::advance(long n) { advance(n, std::numeric_limits<double>::quiet_NaN()); }

void Progress::advance(long n, double seconds_left) {
  done_ += n;
  if (!enabled_) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (t < delay_s_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  // The count read under the lock, not the one this call made: a thread that lost the race
  // for the lock would otherwise print an older count after a newer one.
  const long done = done_.load();
  const double interval = terminal_ ? 0.25 : 2.0;
  if (last_shown_ >= 0 && t - last_shown_ < interval && done != total_) return;
  last_shown_ = t;
  const std::string text = "kincal " + command_ + ": " +
                           (std::isnan(seconds_left) ? line(done, total_, unit_, t)
                                                     : line(done, total_, unit_, t, seconds_left));
  if (terminal_) {
    // \33[K clears what a longer earlier line left.
    err() << "\r" << text << "\33[K";
    open_line_ = true;
  } else {
    err() << text << "\n";
  }
  err().flush();
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!open_line_) return;
  err() << "\n";
  err().flush();
  open_line_ = false;
}

}  // namespace kincal::cli
