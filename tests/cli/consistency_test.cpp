// Issue 14, items 4 and 5: one consistent CLI (--json everywhere, --version, list, batch
// fk/ik, the angle rule, CSV separators, one directory rule, readable defaults) and long runs
// (progress with time remaining, Ctrl-C writes what finished), through the real binary.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;
namespace fs = std::filesystem;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string replace_all(std::string text, char from, char to) {
  for (char& c : text)
    if (c == from) c = to;
  return text;
}

// The data lines of a CSV written by simulate (comment lines dropped).
std::string without_comments(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind('#', 0) != 0) out += line + "\n";
  return out;
}

class CliConsistency : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    const auto sim =
        run_cli("simulate --model " + m_ +
                " --poses 40 --noise-half-width 0.001 --validation 5 --seed 3 --write-data " + d_);
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  TempDir dir_{"consistency"};
  const std::string m_ = dir_ / "M.json", d_ = dir_ / "D.csv";
};

TEST(CliVersion, EveryCommandAndTheProgramPrintTheVersionAndBackends) {
  const auto top = run_cli("--version");
  ASSERT_EQ(top.exit_code, 0) << top.err;
  EXPECT_TRUE(std::regex_search(top.out, std::regex("^kincal [0-9]+\\.[0-9]+\\.[0-9]+")))
      << top.out;
  EXPECT_NE(top.out.find("solver backends: "), std::string::npos) << top.out;
  EXPECT_NE(top.out.find(" gn"), std::string::npos) << top.out;
  for (const char* command : {"list", "simulate", "reproduce", "model", "fk", "ik", "calibrate",
                              "observability", "solver-suite", "verify"}) {
    const auto r = run_cli(std::string(command) + " --version");
    EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
    EXPECT_EQ(r.out, top.out) << command;
  }
}

TEST(CliList, NoArgumentListsEverySection) {
  const auto r = run_cli("list");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* section :
       {"solvers:\n", "models:\n", "mechanisms:\n", "sensors:\n", "constraints:\n"})
    EXPECT_NE(r.out.find(section), std::string::npos) << section << "\n" << r.out;
  EXPECT_NE(r.out.find("cube-hexapod"), std::string::npos);
  EXPECT_NE(r.out.find("length-gauge"), std::string::npos);
  EXPECT_NE(r.out.find("\nfixture-distance "), std::string::npos) << r.out;
  const auto j = run_cli("list --json -");
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const Json list = Json::parse(j.out);
  for (const char* section : {"solvers", "models", "mechanisms", "sensors", "constraints"})
    EXPECT_FALSE(list[section].empty()) << section;
  const auto one = Json::parse(run_cli("list models --json -").out);
  EXPECT_EQ(one.size(), 3u);  // format, version and the one section
  EXPECT_FALSE(one.contains("solvers"));
  EXPECT_EQ(one["models"][0]["name"].is_string(), true);
}

// Every option with a default shows it as a person writes it: no 9.9999999999999995e-07.
TEST(CliHelp, DefaultsAreWrittenAsAPersonWouldWriteThem) {
  for (const char* command : {"list", "simulate", "reproduce", "model", "fk", "ik", "calibrate",
                              "observability", "solver-suite", "verify"}) {
    const auto r = run_cli(std::string(command) + " --help");
    EXPECT_EQ(r.exit_code, 0) << command;
    EXPECT_FALSE(std::regex_search(r.out, std::regex("[0-9]\\.?[0-9]*(99999|00000)[0-9]")))
        << command << ":\n"
        << r.out;
    // model's output is itself JSON (a model file, --out); every other command has --json.
    if (std::string(command) != "model") {
      EXPECT_NE(r.out.find("--json"), std::string::npos) << command << " has no --json";
    }
  }
  EXPECT_NE(run_cli("calibrate --help").out.find("(=1e-06)"), std::string::npos);
  EXPECT_NE(run_cli("observability --help").out.find("(=1e-06)"), std::string::npos);
}

TEST_F(CliConsistency, EveryCommandWritesJson) {
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"simulate --case 1 --solver gn --validation 5", "termination"},
      {"reproduce --trials 1 --solver gn --validation 2 --max-iterations 3 --out " + dir_ / "rep",
       "cases"},
      {"calibrate --model " + m_ + " --data " + d_, "parameters"},
      {"observability --model " + m_ + " --data " + d_, "numerical_rank"},
      {"fk --model " + m_ + " --actuators 354,354,354,354,354,382", "pose"},
      {"ik --model " + m_ + " --pose 0,0,410,0,0,0", "actuators"},
      {"list", "solvers"},
      {"solver-suite --solver gn --problem rosenbrock", "solvers"},
  };
  for (const auto& [args, field] : commands) {
    const auto r = run_cli(args + " --json -");
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
    Json j;
    ASSERT_NO_THROW(j = Json::parse(r.out)) << args << ": stdout is not only the JSON:\n" << r.out;
    EXPECT_TRUE(j.contains(field)) << args;
  }
}

TEST_F(CliConsistency, CalibrateReportIsAnAliasOfJson) {
  const std::string base = "calibrate --model " + m_ + " --data " + d_;
  const auto a = run_cli(base + " --json " + dir_ / "a.json");
  const auto b = run_cli(base + " --report " + dir_ / "b.json");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  Json ja = Json::parse(read_text(dir_ / "a.json")), jb = Json::parse(read_text(dir_ / "b.json"));
  EXPECT_EQ(ja["parameters"], jb["parameters"]);
  EXPECT_EQ(ja["format"], "kincal-calibration-report");
  const auto both = run_cli(base + " --json " + dir_ / "c.json" + " --report " + dir_ / "d.json");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_EQ(count_lines(both.err), 1) << both.err;
  EXPECT_NE(both.err.find("give --json or --report"), std::string::npos) << both.err;
  EXPECT_FALSE(fs::exists(dir_ / "c.json"));
  // The report names its model for verify, which answers in JSON too.
  ASSERT_EQ(run_cli(base + " --json " + dir_ / "r.json" + " --out " + dir_ / "C.json").exit_code,
            0);
  const auto v = run_cli("verify --report " + dir_ / "r.json" + " --json -");
  ASSERT_EQ(v.exit_code, 0) << v.err;
  EXPECT_EQ(Json::parse(v.out)["match"], true);
}

TEST_F(CliConsistency, BatchForwardKinematicsGivesAPosePerRowAndStatuses) {
  // Row 3 cannot be reached: a negative leg.
  std::string csv = without_comments(read_text(d_));
  csv += "-354,354,354,354,354,382,300\n";
  write(dir_ / "q.csv", csv);
  const auto r = run_cli("fk --model " + m_ + " --data " + dir_ / "q.csv" + " --out " +
                         dir_ / "fk.csv" + " --json " + dir_ / "fk.json");
  EXPECT_EQ(r.exit_code, 1) << r.err;  // one row failed: it says so, everything is written
  EXPECT_NE(r.err.find("1 of 41 rows failed"), std::string::npos) << r.err;
  const std::string table = read_text(dir_ / "fk.csv");
  EXPECT_EQ(table.substr(0, table.find('\n')),
            "line,leg1,leg2,leg3,leg4,leg5,leg6,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg,gauge,status,"
            "reason");
  EXPECT_EQ(count_lines(table), 42);
  const Json j = Json::parse(read_text(dir_ / "fk.json"));
  ASSERT_EQ(j["rows"].size(), 41u);
  EXPECT_EQ(j["failed"], 1);
  EXPECT_EQ(j["units"]["leg1"], "mm");
  const Json& bad = j["rows"][40];
  EXPECT_EQ(bad["line"], 42);  // the header is line 1, the 40 rows lines 2-41
  EXPECT_NE(bad["status"], "ok");
  EXPECT_TRUE(bad["pose"]["x_mm"].is_null());
  EXPECT_EQ(bad["actuators"]["leg1"], -354);
  // Each good row is what the single-configuration fk prints.
  const Json& first = j["rows"][0];
  EXPECT_EQ(first["status"], "ok");
  std::string q;
  for (const char* leg : {"leg1", "leg2", "leg3", "leg4", "leg5", "leg6"})
    q += (q.empty() ? "" : ",") + first["actuators"][leg].dump();
  const Json single =
      Json::parse(run_cli("fk --model " + m_ + " --actuators " + q + " --json -").out);
  EXPECT_EQ(single["pose"], first["pose"]);
  EXPECT_EQ(single["readings"], first["readings"]);
}

TEST_F(CliConsistency, BatchInverseKinematicsRoundTripsThroughFk) {
  write(dir_ / "poses.csv",
        "# poses in mm and degrees\nrx_deg,ry_deg,rz_deg,x_mm,y_mm,z_mm,comment\n"
        "0,0,0,0,0,410,1\n1.5,-2,3,5,-4,400,2\n0,0,0,1e308,0,410,3\n");
  const auto ik = run_cli("ik --model " + m_ + " --data " + dir_ / "poses.csv" + " --json -");
  EXPECT_EQ(ik.exit_code, 1) << ik.err;  // the third pose overflows the arithmetic
  const Json j = Json::parse(ik.out);
  ASSERT_EQ(j["rows"].size(), 3u);
  EXPECT_EQ(j["rows"][2]["status"], "non_finite") << j["rows"][2];
  EXPECT_TRUE(j["rows"][2]["actuators"]["leg1"].is_null());
  // The second pose's actuator values give back the pose through fk.
  const Json& row = j["rows"][1];
  ASSERT_EQ(row["status"], "ok");
  std::string q;
  for (const char* leg : {"leg1", "leg2", "leg3", "leg4", "leg5", "leg6"})
    q += (q.empty() ? "" : ",") + row["actuators"][leg].dump();
  const Json fk = Json::parse(run_cli("fk --model " + m_ + " --actuators " + q + " --json -").out);
  for (const auto& [name, value] : row["pose"].items())
    EXPECT_NEAR(fk["pose"][name].get<double>(), value.get<double>(), 1e-6) << name;
  // The CSV form, to standard output by default.
  const auto csv = run_cli("ik --model " + m_ + " --data " + dir_ / "poses.csv");
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')),
            "line,leg1,leg2,leg3,leg4,leg5,leg6,x_mm,y_mm,z_mm,rx_deg,ry_deg,rz_deg,gauge,status,"
            "reason");
  EXPECT_EQ(count_lines(csv.out), 4);
  // A poses file without the unit in its columns is refused, naming the columns.
  write(dir_ / "bare.csv", "x,y,z,rx,ry,rz\n0,0,410,0,0,0\n");
  const auto bare = run_cli("ik --model " + m_ + " --data " + dir_ / "bare.csv");
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("header has no column 'x_mm'"), std::string::npos) << bare.err;
}

TEST_F(CliConsistency, SemicolonAndTabFilesAreReadOrRefusedNeverMisread) {
  const std::string base = "calibrate --model " + m_ + " --json - --data ";
  const auto plain = run_cli(base + d_);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const Json expected = Json::parse(plain.out)["parameters"];
  const std::string csv = read_text(d_);
  write(dir_ / "semi.csv", replace_all(csv, ',', ';'));
  write(dir_ / "tab.csv", replace_all(csv, ',', '\t'));
  for (const char* name : {"semi.csv", "tab.csv"}) {
    const auto r = run_cli(base + dir_ / name);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_EQ(Json::parse(r.out)["parameters"], expected) << name;
    EXPECT_NE(r.err.find("fields separated by"), std::string::npos) << r.err;
  }
  // A decimal comma: one line naming it, never 1,5 read as 1 or 15.
  std::string decimal = replace_all(replace_all(csv, ',', ';'), '.', ',');
  write(dir_ / "decimal.csv", decimal.substr(decimal.find("leg1")));
  const auto r = run_cli(base + dir_ / "decimal.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("decimal.csv:2: field 'leg1'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("has a decimal comma"), std::string::npos) << r.err;
  // Separators mixed in the header: the message names what it found.
  write(dir_ / "mixed.csv", "leg1;leg2;leg3;leg4;leg5;leg6,gauge\n1;2;3;4;5;6,7\n");
  const auto mixed = run_cli(base + dir_ / "mixed.csv");
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_NE(mixed.err.find("the header holds commas and ';'"), std::string::npos) << mixed.err;
}

// The directory rule: every output's missing parent directories are created when it is
// written; nothing is created when the run stops before writing.
TEST_F(CliConsistency, EveryOutputCreatesItsMissingDirectories) {
  const std::string base = "calibrate --model " + m_ + " --data " + d_;
  const auto r =
      run_cli(base + " --out " + dir_ / "new/a/C.json" + " --json " + dir_ / "new/b/R.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "new/a/C.json"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "new/b/R.json"));
  for (const std::string& args :
       {"simulate --case 1 --solver gn --validation 2 --json " + dir_ / "s/x/S.json",
        "model --out " + dir_ / "m/y/M.json",
        "reproduce --trials 1 --solver gn --validation 2 --max-iterations 2 --out " +
            dir_ / "r/z/out"}) {
    const auto s = run_cli(args);
    EXPECT_EQ(s.exit_code, 0) << args << ": " << s.err;
  }
  EXPECT_TRUE(fs::is_regular_file(dir_ / "s/x/S.json"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "m/y/M.json"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "r/z/out/summary.csv"));
  // Bad input: nothing is created.
  const auto bad = run_cli("calibrate --model " + m_ + " --data " + dir_ / "none.csv" + " --out " +
                           dir_ / "never/C.json");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir_ / "never"));
  // Two new files in the same new directory are still the same file.
  const auto same =
      run_cli(base + " --out " + dir_ / "n2/C.json" + " --json " + dir_ / "n2/../n2/C.json");
  EXPECT_EQ(same.exit_code, 2);
  // A path through a file cannot be created: one line, before any work.
  write(dir_ / "plain", "x");
  const auto through = run_cli(base + " --out " + dir_ / "plain/C.json");
  EXPECT_EQ(through.exit_code, 2);
  EXPECT_NE(through.err.find("plain' is not a directory"), std::string::npos) << through.err;
}

// ---- long runs: progress and Ctrl-C ------------------------------------------------------

// A kincal process; killed (SIGKILL) and reaped if a failed assertion leaves it running.
struct Child {
  pid_t pid = -1;
  std::string err_file;
  bool reaped = false;
  Child() = default;
  Child(const Child&) = delete;
  ~Child() {
    if (pid > 0 && !reaped) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
};

// Starts kincal with `args` (no shell), stdout to /dev/null and stderr to a file.
void start(Child& child, const std::vector<std::string>& args, const std::string& err_file) {
  child.err_file = err_file;
  child.pid = ::fork();
  if (child.pid == 0) {
    const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, STDIN_FILENO);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    ::signal(SIGINT, SIG_DFL);
    std::vector<char*> argv{const_cast<char*>(KINCAL_CLI_PATH)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(KINCAL_CLI_PATH, argv.data());
    ::_exit(127);
  }
}

// Waits (up to a minute) until the child's stderr holds `text`.
bool wait_for(const Child& child, const std::string& text) {
  for (int i = 0; i < 6000; ++i) {
    if (read_text(child.err_file).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// Waits (up to a minute) until the child catches SIGINT (its handler is installed): the
// SigCgt mask of /proc/<pid>/status, bit SIGINT - 1.
bool wait_for_sigint_handler(const Child& child) {
  for (int i = 0; i < 6000; ++i) {
    std::ifstream status("/proc/" + std::to_string(child.pid) + "/status");
    std::string line;
    while (std::getline(status, line))
      if (line.rfind("SigCgt:", 0) == 0 &&
          (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1) & 1))
        return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

int wait_status(Child& child) {
  int status = 0;
  ::waitpid(child.pid, &status, 0);
  child.reaped = true;
  return status;
}

TEST(CliLongRuns, ProgressShowsTheTimeRemainingOnlyWhenAsked) {
  TempDir dir("progress");
  // One thread: with two, the second trial can finish before the first one's line is shown.
  const std::string run =
      "reproduce --trials 2 --solver gn --validation 2 --max-iterations 2 --threads 1 ";
  const auto quiet = run_cli(run + "--out " + dir / "a");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");  // stderr is not a terminal: no progress
  const auto shown = run_cli(run + "--progress --out " + dir / "b");
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_NE(shown.err.find("kincal reproduce: 1/10 trials"), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("left"), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find("10/10 trials"), std::string::npos) << shown.err;
}

TEST(CliLongRuns, SolverSuiteShowsProgressWhenAsked) {
  const std::string run = "solver-suite --solver gn --problem rosenbrock";
  EXPECT_EQ(run_cli(run).err, "");
  const auto shown = run_cli(run + " --progress");
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_NE(shown.err.find("kincal solver-suite: 1/"), std::string::npos) << shown.err;
  EXPECT_NE(shown.err.find(" runs, "), std::string::npos) << shown.err;
}

TEST(CliLongRuns, FirstCtrlCWritesTheFinishedTrialsMarkedPartial) {
  TempDir dir("sigint");
  Child child;
  start(child,
        {"reproduce", "--trials", "100000", "--solver", "gn", "--threads", "2", "--validation", "5",
         "--max-iterations", "3", "--progress", "--out", dir / "out", "--json", dir / "r.json"},
        dir / "err.txt");
  ASSERT_TRUE(wait_for(child, "left")) << read_text(dir / "err.txt");
  ::kill(child.pid, SIGINT);
  const int status = wait_status(child);
  const std::string err = read_text(dir / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << err;
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  EXPECT_NE(err.find("interrupted: finishing the items under way"), std::string::npos) << err;
  EXPECT_NE(err.find("kincal reproduce: interrupted: wrote the "), std::string::npos) << err;
  // The tables are whole and say partial; the trials written are the ones that finished.
  const std::string summary = read_text(dir / "out/summary.csv");
  EXPECT_EQ(count_lines(summary), 6) << summary;
  EXPECT_NE(summary.find(",partial\n"), std::string::npos);
  EXPECT_EQ(summary.find(",false\n"), std::string::npos) << summary;
  const Json j = Json::parse(read_text(dir / "r.json"));
  EXPECT_EQ(j["partial"], true);
  int trials = 0;
  for (const auto& c : j["cases"]) trials += c["trials"].get<int>();
  EXPECT_GT(trials, 0);
  EXPECT_LT(trials, 500000);
  EXPECT_EQ(count_lines(read_text(dir / "out/trials.csv")), trials + 1);
}

TEST(CliLongRuns, CtrlCStopsTheSolverSuiteAndWritesWhatFinished) {
  TempDir dir("sigint-suite");
  Child child;
  start(child, {"solver-suite", "--progress", "--json", dir / "s.json"}, dir / "err.txt");
  ASSERT_TRUE(wait_for(child, "left")) << read_text(dir / "err.txt");
  ::kill(child.pid, SIGINT);
  const int status = wait_status(child);
  const std::string err = read_text(dir / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << err;
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  EXPECT_NE(err.find("kincal solver-suite: interrupted: "), std::string::npos) << err;
  const Json j = Json::parse(read_text(dir / "s.json"));
  EXPECT_EQ(j["partial"], true);
  int runs = 0;
  for (const auto& s : j["solvers"]) runs += s["cases"].get<int>();
  EXPECT_GT(runs, 0);
}

// design (issue 21 item 3): progress per stage, and the first Ctrl-C ends the run with the
// best design found so far, whole and marked partial, exit code 130.
TEST(CliLongRuns, FirstCtrlCEndsTheDesignWithTheBestSoFarMarkedPartial) {
  TempDir dir("sigint-design");
  const std::string m = dir / "m.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  Child child;
  // Many candidates and the bound: several seconds of exchange and bound iterations.
  start(child,
        {"design", "--model", m, "--poses", "60", "--candidates", "200000", "--criterion", "I",
         "--bound", "--noise-std", "0.0072mm", "--progress", "--out", dir / "t.csv", "--json",
         dir / "d.json"},
        dir / "err.txt");
  ASSERT_TRUE(wait_for(child, "left")) << read_text(dir / "err.txt");
  ::kill(child.pid, SIGINT);
  const int status = wait_status(child);
  const std::string err = read_text(dir / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << err;
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  EXPECT_NE(err.find("kincal design: interrupted in the "), std::string::npos) << err;
  EXPECT_NE(err.find("wrote the best design found so far, marked partial"), std::string::npos)
      << err;
  const Json j = Json::parse(read_text(dir / "d.json"));
  EXPECT_EQ(j["partial"], true);
  ASSERT_TRUE(j["stopped_in"].is_string()) << j.dump();
  EXPECT_TRUE(j["exchange"]["value"].is_number());
  const std::string t = read_text(dir / "t.csv");
  EXPECT_NE(t.find("# PARTIAL: interrupted in the "), std::string::npos) << t;
  std::istringstream rows(t);
  int data_rows = 0;
  for (std::string line; std::getline(rows, line);)
    if (!line.empty() && line[0] != '#') ++data_rows;
  EXPECT_EQ(data_rows, 61) << "header and the 60 configurations";
}

TEST(CliLongRuns, DesignProgressShowsOnlyWhenAskedAndOnlyForLongStages) {
  TempDir dir("design-progress");
  const std::string m = dir / "m.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  const auto quick = run_cli("design --model " + m +
                             " --poses 30 --candidates 300 --noise-std 0.0072mm --progress --out " +
                             dir / "t.csv");
  ASSERT_EQ(quick.exit_code, 0) << quick.err;
  EXPECT_EQ(quick.err, "") << "a stage under a second says nothing";
}

TEST(CliLongRuns, SecondCtrlCAbortsAtOnceAndWritesNothing) {
  TempDir dir("sigint2");
  // Slow trials (tracking the error over many validation poses at every iteration), so the
  // second Ctrl-C arrives while the first trials are still under way.
  Child child;
  start(child,
        {"reproduce", "--trials", "100", "--solver", "gn", "--threads", "1", "--validation",
         "200000", "--out", dir / "out"},
        dir / "err.txt");
  ASSERT_TRUE(wait_for_sigint_handler(child)) << read_text(dir / "err.txt");
  ::kill(child.pid, SIGINT);
  ASSERT_TRUE(wait_for(child, "Ctrl-C again to abort")) << read_text(dir / "err.txt");
  ::kill(child.pid, SIGINT);
  const int status = wait_status(child);
  ASSERT_TRUE(WIFSIGNALED(status)) << read_text(dir / "err.txt");
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace kincal
