// kincal solver-suite through the real binary.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

TEST(CliSolverSuite, RunsTheChosenBackendsOnTheChosenProblems) {
  const auto r = run_cli("solver-suite --solver lm --solver gn --problem rosenbrock");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // Rosenbrock and the extended Rosenbrock, three starts each.
  EXPECT_NE(r.out.find("lm                                 solved   6/6"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("contract violations 0"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(r.out), 2) << r.out;
  const auto verbose = run_cli("solver-suite --solver lm --problem mgh01 --verbose");
  EXPECT_EQ(count_lines(verbose.out), 4) << verbose.out;
  EXPECT_NE(verbose.out.find("mgh01_rosenbrock from 100x0: converged"), std::string::npos)
      << verbose.out;
}

TEST(CliSolverSuite, JsonHasEveryResultAndTheTally) {
  TempDir dir("solver-suite");
  const auto r =
      run_cli("solver-suite --solver lm --problem jennrich --json " + (dir / "suite.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(read_text(dir / "suite.json"));
  ASSERT_EQ(j["solvers"].size(), 1u);
  const auto& lm = j["solvers"][0];
  EXPECT_EQ(lm["name"], "lm");
  EXPECT_EQ(lm["cases"], 2);  // 100 x0 overflows: listed, not run
  ASSERT_EQ(lm["results"].size(), 3u);
  EXPECT_EQ(lm["results"][2]["start"], "100x0");
  EXPECT_EQ(lm["results"][2]["evaluable"], false);
  EXPECT_NE(lm["results"][2]["why_not_evaluable"].get<std::string>().find("overflow"),
            std::string::npos);
  for (const char* field : {"termination", "message", "final_cost", "outcome", "contract"})
    EXPECT_TRUE(lm["results"][0].contains(field)) << field;
  EXPECT_EQ(lm["results"][0]["contract"]["ok"], true);
  // To stdout the table goes to stderr, the JSON alone to stdout.
  const auto piped = run_cli("solver-suite --solver gn --problem mgh01 --json -");
  ASSERT_EQ(piped.exit_code, 0);
  EXPECT_TRUE(nlohmann::json::accept(piped.out)) << piped.out;
  EXPECT_NE(piped.err.find("gn "), std::string::npos);
}

TEST(CliSolverSuite, ListsTheProblems) {
  const auto r = run_cli("solver-suite --list");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("mgh35_chebyquad_n10"), std::string::npos);
  EXPECT_NE(r.out.find("x0,10x0,100x0(!)"), std::string::npos) << r.out;  // Jennrich-Sampson
  EXPECT_EQ(count_lines(r.out), 1 + 41 + 1);
}

TEST(CliSolverSuite, BadInputGivesOneLineAndExitCode2BeforeAnyWork) {
  for (const std::string args :
       {"--solver no-such-solver", "--problem no_such_problem",
        "--solver lm --solver gn "
        "--solver-option loss=huber:1",
        "--solver lm --solver-option no_such_key=1", "--solver lm --max-iterations -1",
        "--solver lm --json /dev/null/suite.json"}) {
    const auto r = run_cli("solver-suite " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
  }
}

}  // namespace
}  // namespace kincal
