#pragma once
// The kincal program as a function: cli/main.cpp calls it, and so can a test or a fuzzer.

namespace kincal::cli {

/// Runs `kincal <command> [options]` with argv[0] the program name. Returns the exit code:
/// 0 done, 1 the solver did not reach a solution, 2 bad input (one line on stderr).
int run(int argc, const char* const* argv);

/// For a process of its own (cli/main.cpp): a closed standard input, output or error is
/// opened on /dev/null read-only, so that a file kincal opens never takes its number and
/// writes to it fail loudly instead of landing in that file; and SIGXFSZ is ignored, so
/// that a file-size limit (ulimit -f) is a write error that kincal reports and cleans up
/// after, not a silent death that leaves a temporary file.
void prepare_process();

}  // namespace kincal::cli
