// libFuzzer target: the files that design, validate and verify read besides model files,
// run in-process through kincal::cli::run (cli/run.hpp) to the end: the input is written to
// a file and given as
//   validate --report IN   (a calibration report: its statistics, its model's SHA-256)
//   verify --report IN     (the same report, for its calibrated_model entry)
//   design --existing IN   (a measurement file or design template, with empty readings)
// Any input must end in exit code 0, 1 or 2, and a 2 must come with exactly one line on
// stderr in kincal's words (no raw exception text such as "std::" or "type_error").
//
// Runs in a fresh temporary directory holding a model M.json stating its noise, simulated
// data D.csv, and the calibration C.json with its report R.json, made by the program itself.
// Since it changes directory, give libFuzzer absolute paths (corpus).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "kincal/cli/run.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& command, const std::string& detail) {
  std::fprintf(stderr, "fuzz_command_inputs: %s\n  command: %s\n  stderr: %s\n", what,
               command.c_str(), detail.c_str());
  std::abort();
}

// Runs `args` in-process; returns the exit code, stderr in `err` (stdout is discarded).
int run(const std::vector<std::string>& args, std::string& err) {
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, error;
  std::streambuf* old_out = std::cout.rdbuf(out.rdbuf());
  std::streambuf* old_err = std::cerr.rdbuf(error.rdbuf());
  const int code = kincal::cli::run(static_cast<int>(argv.size()), argv.data());
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  err = error.str();
  return code;
}

void check(const std::vector<std::string>& args, const std::string& input) {
  std::string err;
  const int code = run(args, err);
  std::string shown;
  for (const auto& a : args) shown += a + " ";
  if (code != 0 && code != 1 && code != 2) fail("exit code other than 0, 1 or 2", shown, err);
  if (code != 2) return;
  // Notes may come first; the error is the last line.
  if (err.size() < 2 || err.back() != '\n') fail("error is not one line of kincal's", shown, err);
  const auto previous = err.rfind('\n', err.size() - 2);
  const std::string message = err.substr(previous == std::string::npos ? 0 : previous + 1);
  if (message.rfind("kincal ", 0) != 0 || message.find(": error: ") == std::string::npos)
    fail("error is not one line of kincal's", shown, err);
  for (const char* raw : {"std::", "type_error", "parse_error", "out_of_range", "basic_string",
                          "vector::", "what():"})
    // Raw exception text, unless the input holds it (a message quotes what it read).
    if (message.find(raw) != std::string::npos && input.find(raw) == std::string::npos)
      fail("raw exception text", shown, message);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char dir_template[] = "/tmp/kincal-fuzz-inputs-XXXXXX";
  if (!::mkdtemp(dir_template) || ::chdir(dir_template) != 0) std::abort();
  std::string err;
  if (run({"kincal", "model", "--out", "plain.json"}, err) != 0) std::abort();
  std::ifstream plain("plain.json");
  std::stringstream text;
  text << plain.rdbuf();
  std::string model = text.str();
  // The gauge's noise, so that validate predicts the residuals.
  const auto brace = model.rfind('}');
  model = model.substr(0, brace) + ",\n  \"reading_std\": {\"gauge\": 0.0072}\n}\n";
  std::ofstream("M.json") << model;
  if (run({"kincal", "simulate", "--model", "M.json", "--poses", "30", "--noise-half-width",
           "0.0125", "--seed", "3", "--validation", "1", "--write-data", "D.csv"},
          err) != 0 ||
      run({"kincal", "calibrate", "--model", "M.json", "--data", "D.csv", "--out", "C.json",
           "--json", "R.json"},
          err) != 0) {
    std::fprintf(stderr, "fuzz_command_inputs: set-up failed: %s\n", err.c_str());
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 65536) return 0;
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::ofstream("IN", std::ios::binary | std::ios::trunc) << input;
  check({"kincal", "validate", "--model", "C.json", "--data", "D.csv", "--report", "IN"}, input);
  check({"kincal", "verify", "--report", "IN", "--model", "C.json"}, input);
  check({"kincal", "design", "--model", "M.json", "--existing", "IN", "--poses", "30",
         "--candidates", "60", "--out", "/dev/null"},
        input);
  return 0;
}
