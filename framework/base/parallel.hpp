#pragma once
// Parallel Monte Carlo trials. Each trial must depend only on its index (derive its seed
// from the index), so results do not depend on the thread count or scheduling.

#include <functional>

namespace kincal {

/// Calls body(i) for i in [0, count) on `threads` worker threads (0 = all cores), handing
/// out indices dynamically. When `progress_label` is non-empty and the run takes more than
/// a couple of seconds, prints "label: done/count" on stderr as it goes. The first
/// exception thrown by a body is rethrown after all workers stop.
void parallel_for(int count, int threads, const std::function<void(int)>& body,
                  const char* progress_label = nullptr);

/// Number of hardware threads, at least 1.
int hardware_threads();

}  // namespace kincal
