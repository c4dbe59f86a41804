// libFuzzer target: the command line of every kincal command, run in-process through
// kincal::cli::run (cli/run.hpp) up to the end of its checks (stop_after_option_checks): the
// option parsing, the value checks, the memory checks of counts and the file checks of
// OutputPlan. The input is split at NUL bytes into arguments. Any command line must end in
// exit code 0 or 2, and a 2 must come with exactly one line on stderr in kincal's words (no
// raw exception text such as "std::..." or "bad_any_cast").
//
// Runs in a fresh temporary directory holding a model file M.json and a measurement file
// D.csv, so that command lines can name existing files; file checks create and remove probe
// files only. Since it changes directory, give libFuzzer absolute paths (corpus, -dict).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "kincal/cli/run.hpp"
#include "kincal/framework/io/output_plan.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& args, const std::string& detail) {
  std::fprintf(stderr, "fuzz_cli_options: %s\n  arguments: %s\n  stderr: %s\n", what, args.c_str(),
               detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char dir_template[] = "/tmp/kincal-fuzz-cli-XXXXXX";
  if (!::mkdtemp(dir_template) || ::chdir(dir_template) != 0) std::abort();
  // Made by the program itself, so the files are what the commands expect.
  const char* model[] = {"kincal", "model", "--out", "M.json"};
  std::ostringstream quiet;
  std::streambuf* out = std::cout.rdbuf(quiet.rdbuf());
  if (kincal::cli::run(4, model) != 0) std::abort();
  std::cout.rdbuf(out);
  std::ofstream("D.csv") << "leg1,leg2,leg3,leg4,leg5,leg6,gauge\n"
                            "354,354,354,354,354,382,310\n";
  kincal::stop_after_option_checks(true);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 2000) return 0;
  std::vector<std::string> args = {"kincal"};
  std::string current;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      args.push_back(current);
      current.clear();
    } else {
      current += static_cast<char>(data[i]);
    }
  }
  args.push_back(current);
  if (args.size() > 30) return 0;
  std::vector<const char*> argv;
  std::string shown;
  for (const auto& a : args) {
    argv.push_back(a.c_str());
    shown += "'" + a + "' ";
  }

  std::ostringstream out, err;
  std::streambuf* old_out = std::cout.rdbuf(out.rdbuf());
  std::streambuf* old_err = std::cerr.rdbuf(err.rdbuf());
  const int code = kincal::cli::run(static_cast<int>(argv.size()), argv.data());
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);

  const std::string message = err.str();
  if (code != 0 && code != 2) fail("exit code other than 0 or 2 before any work", shown, message);
  if (code == 2 && args.size() > 1 && !message.empty()) {
    if (message.back() != '\n' || message.find('\n') != message.size() - 1)
      fail("error is not one line", shown, message);
    if (message.rfind("kincal", 0) != 0) fail("error does not start with kincal", shown, message);
    // Raw exception text, unless the command line itself holds it (it is then quoted).
    for (const char* raw : {"std::", "bad_any_cast", "basic_string", "bad_lexical_cast", "stoi",
                            "stod", "vector::", "what():"})
      if (message.find(raw) != std::string::npos && shown.find(raw) == std::string::npos)
        fail("raw exception text", shown, message);
  }
  return 0;
}
