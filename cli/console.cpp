#include "kincal/cli/console.hpp"

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <iostream>
#include <vector>

namespace kincal::cli {

namespace {

// Null: the process's streams. Atomic because a command's worker threads read them.
std::atomic<std::ostream*> g_out{nullptr};
std::atomic<std::ostream*> g_err{nullptr};

}  // namespace

std::ostream& out() {
  std::ostream* s = g_out.load();
  return s ? *s : std::cout;
}

std::ostream& err() {
  std::ostream* s = g_err.load();
  return s ? *s : std::cerr;
}

bool out_is_process_stdout() { return g_out.load() == nullptr; }
bool err_is_process_stderr() { return g_err.load() == nullptr; }

const StandardOutput& console_output() {
  class Console final : public StandardOutput {
   public:
    std::ostream& stream() const override { return out(); }
    bool is_process_stdout() const override { return out_is_process_stdout(); }
  };
  static const Console console;
  return console;
}

ConsoleScope::ConsoleScope(std::ostream& out, std::ostream& err)
    : saved_out_(g_out.exchange(&out)), saved_err_(g_err.exchange(&err)) {}

ConsoleScope::~ConsoleScope() {
  g_out.store(saved_out_);
  g_err.store(saved_err_);
}

}  // namespace kincal::cli
