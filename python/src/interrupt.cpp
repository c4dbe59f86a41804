#include "interrupt.hpp"

#include <atomic>
#include <csignal>
#include <mutex>

#include "bindings.hpp"

namespace kincal::python {

namespace {

std::atomic<bool> g_sigint{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the flag is set in a signal handler");
struct sigaction g_previous {};
// One thread's scopes at a time: the handler and the solver check are process-wide. Recursive:
// a Python callback inside a solve may call kincal again on the same thread.
std::recursive_mutex g_scope_mutex;
int g_depth = 0;

extern "C" void on_sigint_in_python_call(int) { g_sigint.store(true); }

}  // namespace

SigintScope::SigintScope(bool active) : active_(active) {
  if (!active_) return;
  g_scope_mutex.lock();
  if (g_depth++ > 0) return;  // the outer scope's handler stays
  g_sigint.store(false);
  struct sigaction action {};
  action.sa_handler = on_sigint_in_python_call;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, &g_previous);
}

SigintScope::~SigintScope() {
  if (!active_) return;
  if (--g_depth == 0) {
    ::sigaction(SIGINT, &g_previous, nullptr);
  }
  g_scope_mutex.unlock();
}

bool SigintScope::interrupted() const { return active_ && g_sigint.load(); }

bool sigint_received() { return g_sigint.load(); }

void bind_interrupt(py::module_& m) {
  m.def(
      "_sigint_received", [] { return sigint_received(); },
      "True when SIGINT arrived during the current kincal call (for tests).");
}

}  // namespace kincal::python
