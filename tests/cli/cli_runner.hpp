#pragma once
// Runs the real kincal binary (KINCAL_CLI_PATH) and captures stdout, stderr and the exit code.

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace kincal::testing {

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// A fresh, empty directory under the system temp dir, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("kincal-test-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string operator/(const std::string& file) const { return (path_ / file).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// `args` is appended to the binary's path as is (quote what needs quoting). `shell_prefix`
/// runs first in the same /bin/sh, e.g. with_file_size_limit().
inline CliResult run_cli(const std::string& args, const std::string& shell_prefix = "") {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(counter++);
  const std::string out_file = (dir / ("kincal-cli-out-" + tag)).string();
  const std::string err_file = (dir / ("kincal-cli-err-" + tag)).string();
  const std::string command = shell_prefix + std::string(KINCAL_CLI_PATH) + " " + args + " >" +
                              out_file + " 2>" + err_file + " </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_text(out_file);
  result.err = read_text(err_file);
  std::filesystem::remove(out_file);
  std::filesystem::remove(err_file);
  return result;
}

/// Runs the binary with its standard output appended to `path` (kincal ... >>path); stderr
/// and the exit code are captured as by run_cli, `out` stays empty.
inline CliResult run_cli_appending_stdout_to(const std::string& args, const std::string& path) {
  const auto err_file = std::filesystem::temp_directory_path() /
                        ("kincal-cli-err-append-" + std::to_string(::getpid()));
  const std::string command = std::string(KINCAL_CLI_PATH) + " " + args + " >>" + path + " 2>" +
                              err_file.string() + " </dev/null";
  const int status = std::system(command.c_str());
  CliResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.err = read_text(err_file.string());
  std::filesystem::remove(err_file);
  return result;
}

/// Shell prefix for run_cli: no file the program writes may grow beyond `blocks` blocks of
/// 512 bytes (1024 when /bin/sh is bash), so writing a larger file fails with EFBIG ("File
/// too large") once it is under way. Unlike permission bits this also stops root. SIGXFSZ
/// is ignored so that the write fails instead of killing the program. The captured stdout
/// and stderr are limited too.
inline std::string with_file_size_limit(int blocks) {
  return "trap '' XFSZ; ulimit -f " + std::to_string(blocks) + "; ";
}

/// Names in `dir` starting with '.': the temporary files of an atomic write.
inline int count_hidden_files(const std::filesystem::path& dir) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    n += entry.path().filename().string()[0] == '.';
  return n;
}

inline int count_lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

}  // namespace kincal::testing
