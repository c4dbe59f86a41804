#pragma once
// Ctrl-C during a long run: the first SIGINT asks the command to stop between items (it
// writes what it finished, marked partial, and says so on stderr); the second one aborts at
// once (the default action, restored by the first: SA_RESETHAND). Commands check
// interrupt_requested() between items (trials, problems); nothing else is interrupted.
//
//   InterruptGuard guard("reproduce");   // installs the handler for its lifetime
//   ... if (interrupt_requested()) skip the item ...

namespace kincal::cli {

class InterruptGuard {
 public:
  /// `command` names the program in the message printed on the first Ctrl-C.
  explicit InterruptGuard(const char* command);
  ~InterruptGuard();  ///< restores the previous SIGINT action
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

/// True after the first SIGINT under an InterruptGuard.
bool interrupt_requested();

}  // namespace kincal::cli
