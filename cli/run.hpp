#pragma once
// The kincal program as a function: cli/main.cpp calls it, and so can a test or a fuzzer.

namespace kincal::cli {

/// Runs `kincal <command> [options]` with argv[0] the program name. Returns the exit code:
/// 0 done, 1 the solver did not reach a solution, 2 bad input (one line on stderr).
int run(int argc, const char* const* argv);

}  // namespace kincal::cli
