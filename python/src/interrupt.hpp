#pragma once
// Ctrl-C during a long call from Python. Python's own SIGINT handler only sets a flag that
// Python code looks at between bytecodes, and none runs while kincal solves with the GIL
// released; so for the length of a call made on the main thread, SigintScope installs a
// handler that sets a flag the solvers' iteration callbacks (sigint_received) and the
// studies' loops read. The call ends at the best point so far (solvers end user_stopped),
// the previous handler is restored, and the caller raises KeyboardInterrupt carrying the
// partial result.

namespace kincal::python {

class SigintScope {
 public:
  /// `active` false (a call from another thread, where Python keeps its handler): does
  /// nothing, and interrupted() stays false.
  explicit SigintScope(bool active);
  ~SigintScope();
  SigintScope(const SigintScope&) = delete;
  SigintScope& operator=(const SigintScope&) = delete;
  /// True once SIGINT arrived during this scope.
  bool interrupted() const;

 private:
  bool active_;
};

/// True while a SigintScope is active and SIGINT has arrived.
bool sigint_received();

}  // namespace kincal::python
