#include "kincal/cli/interrupt.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace kincal::cli {

namespace {

std::atomic<bool> g_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the flag is set in a signal handler");
char g_message[160];
std::size_t g_message_length = 0;
struct sigaction g_previous {};

// Only async-signal-safe calls here: an atomic store and write(2).
extern "C" void on_sigint(int) {
  g_requested.store(true);
  const ssize_t unused = ::write(STDERR_FILENO, g_message, g_message_length);
  (void)unused;
}

}  // namespace

InterruptGuard::InterruptGuard(const char* command) {
  g_requested.store(false);
  std::snprintf(g_message, sizeof g_message,
                "\nkincal %s: interrupted: finishing the items under way, then writing what "
                "is done (Ctrl-C again to abort)\n",
                command);
  g_message_length = std::strlen(g_message);
  struct sigaction action {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  // The second Ctrl-C finds the default action again: it ends the process at once.
  action.sa_flags = SA_RESETHAND;
  ::sigaction(SIGINT, &action, &g_previous);
}

InterruptGuard::~InterruptGuard() { ::sigaction(SIGINT, &g_previous, nullptr); }

bool interrupt_requested() { return g_requested.load(); }

}  // namespace kincal::cli
