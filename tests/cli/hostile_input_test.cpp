// The cases of the hostile-input audit (issue 9) that used to end badly, through the real
// binary: each now gives one line naming what and where, a non-zero exit, and nothing written.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace kincal {
namespace {

namespace fs = std::filesystem;
using kincal::testing::count_lines;
using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// One line on stderr containing `expected`, exit code 2.
void expect_one_line_error(const kincal::testing::CliResult& r, const std::string& expected,
                           const std::string& context) {
  EXPECT_EQ(r.exit_code, 2) << context << "\n" << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << context << "\n" << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << context << "\n  got: " << r.err;
}

class CliHostileInput : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    const auto sim =
        run_cli("simulate --model " + m_ +
                " --poses 40 --noise-half-width 0.0125 --seed 3 --solver gn --validation 1 "
                "--write-data " +
                d_);
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  // D.csv with line `line` (1-based) replaced by `text`.
  std::string data_with_line(int line, const std::string& text) const {
    std::istringstream in(read_text(d_));
    std::string out, l;
    for (int n = 1; std::getline(in, l); ++n) out += (n == line ? text : l) + "\n";
    return out;
  }
  // M.json with `edit` applied.
  std::string model_with(const std::function<void(Json&)>& edit) const {
    Json j = Json::parse(read_text(m_));
    edit(j);
    return j.dump(2);
  }
  TempDir dir_{"hostile"};
  std::string m_ = dir_ / "M.json", d_ = dir_ / "D.csv";
};

// "--poses 2147483647 gives std::bad_alloc and leaves an empty --out directory".
TEST_F(CliHostileInput, CountsBeyondMemoryAreRefusedBeforeAnyWorkOrOutput) {
  const std::string out = dir_ / "out", json = dir_ / "S.json";
  for (const std::string& args :
       {"simulate --poses 2147483647 --json " + json,
        "simulate --validation 2147483647 --json " + json,
        "observability --model " + m_ + " --poses 2147483647 --json " + json,
        "reproduce --trials 2147483647 --out " + out,
        "reproduce --trials 1 --validation 2147483647 --out " + out}) {
    const auto r = run_cli(args);
    // The message names the option that asks too much ("--poses 2147483647").
    const auto count = args.find(" 2147483647"), start = args.rfind("--", count);
    const std::string option = args.substr(start, count + 11 - start);
    expect_one_line_error(r, option + ": needs about", args);
    EXPECT_NE(r.err.find("of memory"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("expected at most about"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
    EXPECT_FALSE(fs::exists(json)) << args;
    EXPECT_EQ(r.out, "") << args;
  }
}

// "--data /dev/zero reads 1 GB before failing": it stops at the first byte now.
TEST_F(CliHostileInput, ABinaryOrEndlessDataFileStopsAtOnce) {
  expect_one_line_error(run_cli("calibrate --model " + m_ + " --data /dev/zero"),
                        "/dev/zero:1: NUL byte at column 1; expected a text file (CSV)",
                        "/dev/zero");
  write(dir_ / "nul.csv",
        data_with_line(5, "354,354,354,354,354,382," + std::string("336.81\0junk", 11)));
  expect_one_line_error(run_cli("calibrate --model " + m_ + " --data " + dir_ / "nul.csv"),
                        "nul.csv:5: NUL byte at column 31", "NUL in a value");
  write(dir_ / "long.csv", data_with_line(6, std::string(70'000, '3')));
  expect_one_line_error(run_cli("calibrate --model " + m_ + " --data " + dir_ / "long.csv"),
                        "long.csv:6: line longer than the limit of 65536 bytes", "long line");
}

TEST_F(CliHostileInput, ValuesAreJudgedWithTheRightWords) {
  // 1e-400 is a number (it rounds to 0), not "not a finite number".
  write(dir_ / "tiny.csv", data_with_line(4, "1e-400,354,354,354,354,382,310"));
  const auto tiny = run_cli("calibrate --model " + m_ + " --data " + dir_ / "tiny.csv");
  EXPECT_EQ(tiny.err.find("not a finite number"), std::string::npos) << tiny.err;
  EXPECT_NE(tiny.err.find("tiny.csv: forward kinematics of the model fails at line 4"),
            std::string::npos)
      << tiny.err;  // a leg length of 0 cannot be reached: judged as the number it is
  // A UTF-8 byte order mark (spreadsheets write one) is not part of the first column name.
  write(dir_ / "bom.csv", "\xEF\xBB\xBF" + read_text(d_));
  const auto bom = run_cli("calibrate --model " + m_ + " --data " + dir_ / "bom.csv");
  EXPECT_EQ(bom.exit_code, 0) << bom.err;
  // A reading that is a number but overflows the sum of squares is named by its line.
  write(dir_ / "huge.csv", data_with_line(7, "354,354,354,354,354,382,1e308"));
  expect_one_line_error(run_cli("calibrate --model " + m_ + " --data " + dir_ / "huge.csv"),
                        "huge.csv:7: field 'gauge': predicted - measured is -1e+308",
                        "gauge 1e308");
}

// Errors in model values used to be blamed on CSV lines.
TEST_F(CliHostileInput, UnusableModelValuesAreBlamedOnTheModel) {
  write(dir_ / "big.json", model_with([](Json& j) {
          j["mechanism"]["legs"][0]["base"] = {1e200, 0, 0};
        }));
  write(dir_ / "far.json", model_with([](Json& j) {
          j["sensors"][0]["base"] = {1e300, 1e300, 0};
        }));
  for (const char* model : {"big.json", "far.json"})
    for (const std::string& command :
         {"calibrate --data " + d_, std::string("observability --poses 30"),
          std::string("fk --actuators 354,354,354,354,354,382"),
          std::string("simulate --poses 30")}) {
      const std::string args = command + " --model " + dir_ / model;
      const auto r = run_cli(args);
      expect_one_line_error(r, dir_ / model + ": the model's values cannot be computed with", args);
      EXPECT_EQ(r.err.find("D.csv"), std::string::npos) << r.err;
    }
  // A usable model that reaches none of the rows: both files are named.
  write(dir_ / "offset.json",
        model_with([](Json& j) { j["mechanism"]["legs"][0]["offset"] = 1e6; }));
  expect_one_line_error(run_cli("calibrate --data " + d_ + " --model " + dir_ / "offset.json"),
                        "D.csv: forward kinematics of the model " + dir_ / "offset.json" +
                            " fails at every row (line 4: ",
                        "offset 1e6");
}

TEST_F(CliHostileInput, ARepeatedKeyInAModelIsAnError) {
  std::string text = read_text(m_);
  text.insert(text.rfind('}'), ",\n  \"free\": [\"gauge.offset\"]\n");
  write(dir_ / "twice.json", text);
  expect_one_line_error(run_cli("calibrate --data " + d_ + " --model " + dir_ / "twice.json"),
                        "twice.json: line ", "duplicate free");
  const auto r = run_cli("calibrate --data " + d_ + " --model " + dir_ / "twice.json");
  EXPECT_NE(r.err.find("key 'free' appears twice in the top-level object"), std::string::npos);
}

TEST_F(CliHostileInput, ADeeplyNestedModelIsAnErrorNotACrash) {
  write(dir_ / "deep.json", std::string(100'000, '[') + std::string(100'000, ']'));
  expect_one_line_error(run_cli("fk --actuators 1,2,3,4,5,6 --model " + dir_ / "deep.json"),
                        "deep.json: line 1, column 65: nesting deeper than 64 levels", "deep");
}

// "ik --pose 1e308,... prints inf with exit 0".
TEST_F(CliHostileInput, KinematicsThatOverflowAreErrors) {
  expect_one_line_error(run_cli("ik --model " + m_ + " --pose 1e308,0,0,0,0,0"),
                        "--pose '1e308,0,0,0,0,0': inverse kinematics non-finite values in the "
                        "pose or the parameters: leg 1 length is not finite",
                        "ik 1e308");
  const auto fk = run_cli("fk --model " + m_ + " --actuators 1e308,1e308,1e308,1e308,1e308,1e308");
  EXPECT_EQ(fk.exit_code, 2) << fk.out;
  EXPECT_EQ(fk.out.find("inf"), std::string::npos) << fk.out;
}

// "A non-UTF-8 --data path fails with a JSON exception, and only after the whole solve."
TEST_F(CliHostileInput, ANonUtf8FileNameIsRefusedBeforeTheSolveWhenTheReportMustNameIt) {
  const std::string latin1 = dir_ / "d\xE9j\xE0.csv";
  fs::copy_file(d_, latin1);
  const auto r =
      run_cli("calibrate --model " + m_ + " --data '" + latin1 + "' --json " + dir_ / "R.json");
  expect_one_line_error(r, "--data: the file name is not valid UTF-8", "latin-1 name");
  EXPECT_EQ(r.out, "");  // no solve
  EXPECT_FALSE(fs::exists(dir_ / "R.json"));
  // Without a report nothing needs to name it.
  EXPECT_EQ(run_cli("calibrate --model " + m_ + " --data '" + latin1 + "'").exit_code, 0);
}

// "simulate exits 0 when its solver failed, while calibrate exits 1."
TEST(CliSimulateOutcome, ASolverThatFailsIsExitCode1WithItsOutputsWritten) {
  TempDir dir("simulate-fails");
  // Plain Gauss-Newton from parameter errors of up to 40 mm leaves the region where forward
  // kinematics works at its first step.
  const auto r =
      run_cli("simulate --param-error 40 --solver gn --validation 1 --json " + dir / "S.json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("kincal simulate: error: the solver did not reach a solution"),
            std::string::npos)
      << r.err;
  const Json j = Json::parse(read_text(dir / "S.json"));
  EXPECT_TRUE(j["termination"] == "diverged" || j["termination"] == "failed") << j["termination"];
}

// Boost.ProgramOptions fills "%name%" placeholders into its messages until none is left,
// forever when the argument itself holds one (found by fuzz_cli_options; it hung the
// program). `timeout` turns a hang into a failure.
TEST(CliMessages, AnArgumentHoldingABoostPlaceholderDoesNotHang) {
  for (const char* args :
       {"reproduce '--trial%original_token%s' 3", "simulate --poses %value%",
        "calibrate --data D.csv --no-such-%canonical_option%", "list %option%"}) {
    const auto r = run_cli(args, "timeout 60 ");
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << args << ": " << r.err;
  }
  // A '%' that is not a placeholder keeps boost's own message.
  const auto plain = run_cli("simulate --poses 50%", "timeout 60 ");
  EXPECT_NE(plain.err.find("the argument ('50%') for option '--poses' is invalid"),
            std::string::npos)
      << plain.err;
}

// Whatever a path or value holds, an error is one line.
TEST(CliMessages, AreOneLineWhateverTheInputHolds) {
  TempDir dir("one-line");
  // A file with a line break in its name, used as a directory (a missing one is created).
  write(dir / "a\nb", "a file");
  const std::string weird = dir / "a\nb/M.json";
  expect_one_line_error(run_cli("model --out '" + weird + "'"), "a\\x0Ab/M.json",
                        "line break in a path");
  expect_one_line_error(run_cli("fk --actuators 1 --model '" + dir / "x\ny.json" + "'"),
                        "x\\x0Ay.json", "line break in a model path");
}

}  // namespace
}  // namespace kincal
