#include "kincal/cli/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

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
  std::string text = std::to_string(done) + "/" + std::to_string(total) + " " + unit + ", " +
                     duration_text(elapsed_s) + " elapsed";
  // The rate so far predicts the rest; nothing to predict from before the first item.
  if (done > 0 && done < total)
    text += ", about " + duration_text(elapsed_s / done * (total - done)) + " left";
  return text;
}

Progress::Progress(std::string command, long total, std::string unit, bool enabled)
    : command_(std::move(command)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(enabled),
      terminal_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::advance(long n) {
  const long done = done_ += n;
  if (!enabled_) return;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::lock_guard<std::mutex> lock(mutex_);
  const double interval = terminal_ ? 0.25 : 2.0;
  if (last_shown_ >= 0 && t - last_shown_ < interval && done != total_) return;
  last_shown_ = t;
  const std::string text = "kincal " + command_ + ": " + line(done, total_, unit_, t);
  if (terminal_) {
    // \33[K clears what a longer earlier line left.
    std::fprintf(stderr, "\r%s\33[K", text.c_str());
    open_line_ = true;
  } else {
    std::fprintf(stderr, "%s\n", text.c_str());
  }
  std::fflush(stderr);
}

void Progress::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!open_line_) return;
  std::fprintf(stderr, "\n");
  std::fflush(stderr);
  open_line_ = false;
}

}  // namespace kincal::cli
