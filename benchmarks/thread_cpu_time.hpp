#pragma once
// CPU time of the calling thread, in ms: what one solve costs while other threads of a study
// keep the other cores busy.

#include <ctime>

namespace kincal {

inline double thread_cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

}  // namespace kincal
