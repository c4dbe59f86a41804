// No output may be an input or another output (framework/io/output_plan.hpp), whatever names them:
// the same name, "./" forms, symbolic and hard links, "-" and /dev/stdout, a redirection of
// standard output. Every refused run leaves every file as it was and writes nothing.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "cli_runner.hpp"

namespace kincal {
namespace {

namespace fs = std::filesystem;
using kincal::testing::count_hidden_files;
using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

class CliOutputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    ASSERT_EQ(run_cli("simulate --model " + m_ +
                      " --poses 30 --seed 2 --solver gn --validation 1 --write-data " + d_)
                  .exit_code,
              0);
    fs::create_symlink("D.csv", dir_.path() / "link.csv");
    fs::create_hard_link(d_, dir_.path() / "hard.csv");
  }
  // Every file in the directory, with its content.
  std::map<std::string, std::string> snapshot() const {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::directory_iterator(dir_.path()))
      files[entry.path().filename().string()] =
          entry.is_regular_file() ? read_text(entry.path().string()) : "(not a file)";
    return files;
  }
  // `args` must fail with one line containing `expected`, writing nothing; with
  // `stdout_to`, standard output is appended to that file (kincal ... >>file).
  void expect_refused(const std::string& args, const std::string& expected,
                      const std::string& stdout_to = "") {
    const auto before = snapshot();
    const auto r = stdout_to.empty()
                       ? run_cli(args)
                       : kincal::testing::run_cli_appending_stdout_to(args, stdout_to);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << "\n  got: " << r.err;
    EXPECT_EQ(snapshot(), before) << args << ": changed a file";
  }
  TempDir dir_{"output-safety"};
  std::string m_ = dir_ / "M.json", d_ = dir_ / "D.csv";
};

// The audit's cases: each replaced an input, or wrote two documents into one file.
TEST_F(CliOutputSafety, TheAuditsCasesAreRefused) {
  const std::string cal = "calibrate --model " + m_ + " --data " + d_;
  expect_refused(cal + " --out " + d_,
                 "--out '" + d_ + "' is the same file as --data '" + d_ + "', an input");
  expect_refused(cal + " --json " + m_,
                 "--json '" + m_ + "' is the same file as --model '" + m_ + "', an input");
  expect_refused(cal + " --out - --json -",
                 "--out '-' (standard output) and --json '-' (standard output) are the same "
                 "file");
  const std::string sim = "simulate --case 1 --solver gn --validation 1";
  expect_refused(sim + " --model " + m_ + " --write-data " + m_,
                 "--write-data '" + m_ + "' is the same file as --model '" + m_ + "'");
  expect_refused(
      sim + " --json " + dir_ / "S.json" + " --trace " + dir_ / "S.json",
      "--json '" + dir_ / "S.json" + "' and --trace '" + dir_ / "S.json" + "' are the same file");
  expect_refused(sim + " --json " + d_ + " --write-data " + d_,
                 "--json '" + d_ + "' and --write-data '" + d_ + "' are the same file");
}

TEST_F(CliOutputSafety, FilesAreComparedByWhatTheyAreNotByName) {
  const std::string cal = "calibrate --model " + m_ + " --data " + d_;
  // Another spelling, a symbolic link, a hard link (same inode, different name).
  expect_refused(cal + " --out " + dir_.path().string() + "/./D.csv", "is the same file as --data");
  expect_refused(cal + " --out " + dir_ / "link.csv", "is the same file as --data");
  expect_refused(cal + " --report " + dir_ / "hard.csv", "is the same file as --data");
  expect_refused("calibrate --model " + m_ + " --data " + dir_ / "link.csv" + " --out " + d_,
                 "is the same file as --data");
  // simulate --write-data D.csv also writes D.truth.json.
  expect_refused(
      "simulate --case 1 --solver gn --validation 1 --model " + dir_ / "D.truth.json" +
          " --write-data " + d_,
      "--write-data's true model '" + dir_ / "D.truth.json" + "' is the same file as --model");
  expect_refused("observability --poses 30 --model " + m_ + " --json " + m_,
                 "--json '" + m_ + "' is the same file as --model");
  // Two new files under one name.
  expect_refused(cal + " --out " + dir_ / "new.json" + " --report " + dir_ / "./new.json",
                 "are the same file");
}

TEST_F(CliOutputSafety, StandardOutputCountsWhateverNamesIt) {
  const std::string cal = "calibrate --model " + m_ + " --data " + d_;
  expect_refused(cal + " --out - --report /dev/stdout", "are the same file");
  expect_refused(cal + " --out /dev/fd/1 --report /proc/self/fd/1", "are the same file");
  // kincal prints to standard output: redirected onto an input, it would append to it.
  expect_refused(cal, "standard output goes to --data '" + d_ + "', an input", d_);
  expect_refused("fk --actuators 354,354,354,354,354,382 --model " + m_,
                 "standard output goes to --model", m_);
  // The null device may be named any number of times: nothing is lost there.
  const auto r = run_cli(cal + " --out /dev/null --report /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// reproduce replaces its --out directory whole, so it must not hold anything else.
TEST_F(CliOutputSafety, ReproduceOwnsItsDirectory) {
  const std::string run = "reproduce --trials 1 --solver gn --validation 2 --out ";
  fs::create_directory(dir_.path() / "results");
  std::ofstream(dir_ / "results/notes.txt") << "mine";
  expect_refused(run + dir_ / "results",
                 "--out '" + dir_ / "results" +
                     "': holds 'notes.txt', which is not one of the "
                     "files this command writes (summary.csv, trials.csv, trace.csv)");
  EXPECT_EQ(read_text(dir_ / "results/notes.txt"), "mine");
  expect_refused(run + d_, "--out '" + d_ + "': exists and is not a directory");
  expect_refused(run + ".", "is the current directory or one of its parents");
  expect_refused(run + "/", "is the root directory");
  // A directory it wrote itself is replaced, and a new one created with its parents.
  const auto first = run_cli(run + dir_ / "a/b/out");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto again = run_cli(run + dir_ / "a/b/out" + " --seed 9");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(read_text(dir_ / "a/b/out/trials.csv"), "");
  EXPECT_EQ(count_hidden_files(dir_.path() / "a/b"), 0);
}

}  // namespace
}  // namespace kincal
