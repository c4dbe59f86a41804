#include "kincal/framework/base/parallel.hpp"

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace kincal {

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

void parallel_for(int count, int threads, const std::function<void(int)>& body,
                  const char* progress_label) {
  if (threads <= 0) threads = hardware_threads();
  threads = std::max(1, std::min(threads, count));
  std::atomic<int> next{0}, done{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto start = std::chrono::steady_clock::now();
  std::mutex progress_mutex;
  double last_report = 0;
  // On a terminal one line is rewritten in place; in a log, a full line every few seconds.
  const bool terminal = isatty(STDERR_FILENO);
  const double report_interval = terminal ? 1.0 : 5.0;

  auto worker = [&] {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= count) return;
      {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (error) return;
      }
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        return;
      }
      const int finished = ++done;
      if (progress_label && *progress_label) {
        const double t =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (t > 2.0 && (t - last_report > report_interval || finished == count)) {
          last_report = t;
          std::fprintf(stderr, "%s%s: %d/%d (%.0f s)%s", terminal ? "\r" : "", progress_label,
                       finished, count, t, terminal && finished != count ? "" : "\n");
          std::fflush(stderr);
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

void parallel_chunks(int count, int chunk_size, const std::function<void(int, int, int)>& body) {
  const int chunks = chunk_count(count, chunk_size);
  auto run = [&](int chunk) {
    body(chunk, chunk * chunk_size, std::min(count, (chunk + 1) * chunk_size));
  };
  if (chunks < 2) {
    for (int chunk = 0; chunk < chunks; ++chunk) run(chunk);
    return;
  }
  parallel_for(chunks, 0, run);
}

}  // namespace kincal
