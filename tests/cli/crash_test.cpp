// What a crash leaves behind (docs/reliability.md, "Outputs"). Each command is killed with
// SIGKILL at every step of writing its files in turn (KINCAL_TEST_KILL_AT_WRITE_STEP, see
// framework/io/output_files.hpp), until a run gets through; after each kill the outputs must be in
// one of the states the documentation promises. Then real `kill -9`s from outside, at
// spread-out moments of a run. Temporary files of killed writers must be cleaned up by the
// next write.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "cli_runner.hpp"

namespace kincal {
namespace {

namespace fs = std::filesystem;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

// A run killed by the hook exits through the shell with 128 + SIGKILL (or is reported as
// signalled).
bool was_killed(const kincal::testing::CliResult& r) {
  return r.exit_code == -1 || r.exit_code == 128 + SIGKILL;
}

kincal::testing::CliResult run_killed_at(int step, const std::string& args) {
  return run_cli(args, "KINCAL_TEST_KILL_AT_WRITE_STEP=" + std::to_string(step) + " ");
}

// Hidden entries left in `dir` must belong to running processes: the temporary files of a
// killed writer are removed by the next write into the same directory.
void expect_no_stale_temporaries(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name[0] != '.') continue;
    const auto tag = name.rfind(".kincal-tmp-");
    ASSERT_NE(tag, std::string::npos) << name;
    const long pid = std::stol(name.substr(tag + 12));
    EXPECT_EQ(::kill(static_cast<pid_t>(pid), 0), 0) << "left behind: " << name;
  }
}

TEST(CliCrash, ASingleFileIsOldOrNewAtEveryStep) {
  TempDir dir("crash-model");
  const std::string m = dir / "M.json";
  std::ofstream(m) << "old";
  ASSERT_EQ(run_cli("model --out " + dir / "reference.json").exit_code, 0);
  const std::string fresh = read_text(dir / "reference.json");
  int kills = 0;
  for (int step = 1; step < 100; ++step) {
    const auto r = run_killed_at(step, "model --out " + m);
    const std::string now = read_text(m);
    EXPECT_TRUE(now == "old" || now == fresh) << "step " << step << ": " << now.substr(0, 80);
    if (!was_killed(r)) {
      ASSERT_EQ(r.exit_code, 0) << r.err;
      break;
    }
    ++kills;
  }
  EXPECT_GE(kills, 4);  // created, written, flushed, renamed, ...
  EXPECT_EQ(read_text(m), fresh);
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  expect_no_stale_temporaries(dir.path());
}

class CliCrashCalibrate : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    for (const auto& [data, seed] : {std::pair{d1_, 1}, std::pair{d2_, 2}})
      ASSERT_EQ(run_cli("simulate --model " + m_ + " --poses 40 --noise-half-width 0.001 --seed " +
                        std::to_string(seed) + " --solver gn --validation 1 --write-data " + data)
                    .exit_code,
                0);
  }
  TempDir dir_{"crash-calibrate"};
  std::string m_ = dir_ / "M.json", d1_ = dir_ / "D1.csv", d2_ = dir_ / "D2.csv";
};

// calibrate writes the report, then the model. Killed anywhere, the pair is old and old,
// new and new, or a new report beside the old model, which `kincal verify` names.
TEST_F(CliCrashCalibrate, ThePairIsConsistentOrTheMismatchIsDetected) {
  const std::string c = dir_ / "out/C.json", r = dir_ / "out/R.json";
  fs::create_directory(dir_.path() / "out");
  // Two iterations are enough (the writing is under test); a model is written after them.
  const std::string solve = " --solver gn --max-iterations 2";
  const std::string outputs = solve + " --out " + c + " --report " + r;
  ASSERT_EQ(run_cli("calibrate --model " + m_ + " --data " + d1_ + outputs).exit_code, 0);
  const std::string old_model = read_text(c);
  ASSERT_EQ(
      run_cli("calibrate --model " + m_ + " --data " + d2_ + solve + " --out " + dir_ / "new.json")
          .exit_code,
      0);
  const std::string new_model = read_text(dir_ / "new.json");
  ASSERT_NE(old_model, new_model);
  const std::string verify = "verify --report " + r + " --model " + c;
  std::set<std::string> states;
  for (int step = 1; step < 100; ++step) {
    const auto run = run_killed_at(step, "calibrate --model " + m_ + " --data " + d2_ + outputs);
    const std::string model = read_text(c);
    const std::string data = Json::parse(read_text(r))["data"];
    const bool model_new = model == new_model, report_new = data == d2_;
    ASSERT_TRUE(model_new || model == old_model) << "step " << step << ": model neither";
    const auto check = run_cli(verify);
    if (model_new == report_new) {
      EXPECT_EQ(check.exit_code, 0) << "step " << step << ": " << check.err;
    } else {
      // The model is renamed last: a new model never stands beside an old report.
      EXPECT_TRUE(report_new) << "step " << step << ": new model, old report";
      EXPECT_EQ(check.exit_code, 1) << "step " << step;
      EXPECT_NE(check.err.find(c + " is not the model " + r + " describes"), std::string::npos)
          << check.err;
    }
    states.insert(std::string(report_new ? "new" : "old") + " report, " +
                  (model_new ? "new" : "old") + " model");
    if (!was_killed(run)) {
      ASSERT_EQ(run.exit_code, 0) << run.err;
      EXPECT_TRUE(model_new && report_new);
      break;
    }
  }
  // Every state was reached, the mismatched one included: the hook hit between the renames.
  EXPECT_EQ(states.size(), 3u);
  ASSERT_EQ(run_cli("calibrate --model " + m_ + " --data " + d2_ + outputs).exit_code, 0);
  expect_no_stale_temporaries(dir_.path() / "out");
}

class CliCrashReproduce : public ::testing::Test {
 protected:
  // As small as a run can be: the writing is under test, not the solving.
  static constexpr const char* kRun =
      "reproduce --trials 1 --solver gn --max-iterations 2 --validation 1 ";
  void SetUp() override {
    for (const auto& [name, seed] : {std::pair{"old", 1}, std::pair{"new", 2}}) {
      const std::string out = dir_ / name;
      ASSERT_EQ(
          run_cli(std::string(kRun) + "--seed " + std::to_string(seed) + " --out " + out).exit_code,
          0);
      // trials.csv holds solve times, which differ between runs: the other two identify a set.
      reference_[name] = read_text(out + "/summary.csv") + read_text(out + "/trace.csv");
    }
  }
  // "old" or "new": which complete set `out` holds; fails the test on a mix.
  std::string which_set(const std::string& out) const {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(out)) names.insert(entry.path().filename());
    EXPECT_EQ(names, (std::set<std::string>{"summary.csv", "trace.csv", "trials.csv"}));
    EXPECT_EQ(kincal::testing::count_lines(read_text(out + "/trials.csv")), 1 + 5 * 1);
    const std::string key = read_text(out + "/summary.csv") + read_text(out + "/trace.csv");
    for (const auto& [name, text] : reference_)
      if (key == text) return name;
    ADD_FAILURE() << "a mix of old and new tables in " << out;
    return "mix";
  }
  TempDir dir_{"crash-reproduce"};
  std::map<std::string, std::string> reference_;
};

// The directory is swapped in one step: killed anywhere, it holds the old set or the new.
TEST_F(CliCrashReproduce, TheDirectoryIsTheOldOrTheNewSetAtEveryStep) {
  const std::string out = dir_ / "out";
  ASSERT_EQ(run_cli(std::string(kRun) + "--seed 1 --out " + out).exit_code, 0);
  std::set<std::string> seen;
  int step = 1;
  for (; step < 100; ++step) {
    const auto run = run_killed_at(step, std::string(kRun) + "--seed 2 --out " + out);
    seen.insert(which_set(out));
    if (!was_killed(run)) {
      ASSERT_EQ(run.exit_code, 0) << run.err;
      break;
    }
  }
  EXPECT_EQ(seen, (std::set<std::string>{"old", "new"}));
  EXPECT_EQ(which_set(out), "new");
  ASSERT_EQ(run_cli(std::string(kRun) + "--seed 2 --out " + out).exit_code, 0);
  expect_no_stale_temporaries(dir_.path());
}

// The same with real `kill -9`s from outside, spread over the second half of a run and just
// beyond it: wherever they land, none may leave a mix.
TEST_F(CliCrashReproduce, ExternalKillsNeverLeaveAMix) {
  const std::string out = dir_ / "out";
  ASSERT_EQ(run_cli(std::string(kRun) + "--seed 1 --out " + out).exit_code, 0);
  // How long a run takes here, to spread the kills over it.
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(run_cli(std::string(kRun) + "--seed 1 --threads 1 --out " + dir_ / "timed").exit_code,
            0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string args = std::string(kRun) + "--seed 2 --threads 1 --out " + out;
  for (int k = 0; k < 10; ++k) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const std::string command = std::string(KINCAL_CLI_PATH) + " " + args + " >/dev/null 2>&1";
      ::execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds * (0.5 + 0.06 * k)));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    which_set(out);
  }
  ASSERT_EQ(run_cli(args).exit_code, 0);
  EXPECT_EQ(which_set(out), "new");
  expect_no_stale_temporaries(dir_.path());
}

}  // namespace
}  // namespace kincal
