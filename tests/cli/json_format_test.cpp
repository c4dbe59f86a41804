// Every command's --json document starts with its format ("kincal-<something>") and a version
// number (cli/common_options.hpp: json_document), so that a reader can tell what it holds.
// The walk covers every command in the program's table: a new command without a case here
// fails the test.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "cli_runner.hpp"
#include "kincal/cli/commands.hpp"

namespace kincal::testing {
namespace {

TEST(CliJson, EveryCommandsDocumentHasAFormatAndAVersion) {
  TempDir dir("json-format");
  const std::string m = dir / "M.json", d = dir / "D.csv", c = dir / "C.json", r = dir / "R.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  ASSERT_EQ(
      run_cli("simulate --model " + m + " --poses 30 --seed 4 --validation 1 --write-data " + d)
          .exit_code,
      0);
  ASSERT_EQ(
      run_cli("calibrate --model " + m + " --data " + d + " --out " + c + " --json " + r).exit_code,
      0);
  // The command line of each command that writes a --json document (given as --json -).
  std::map<std::string, std::string> commands = {
      {"list", "list"},
      {"simulate", "simulate --case 1 --validation 1"},
      {"reproduce", "reproduce --trials 1"},
      {"fk", "fk --model " + m + " --actuators 354,354,354,354,354,382"},
      {"ik", "ik --model " + m + " --pose 0,0,300,0,0,0"},
      {"calibrate", "calibrate --model " + m + " --data " + d},
      {"observability", "observability --model " + m + " --data " + d},
      {"validate", "validate --model " + c + " --data " + d + " --report " + r},
      {"design",
       "design --model " + m + " --poses 30 --candidates 60 --noise-std 0.0072mm --out /dev/null"},
      {"solver-suite", "solver-suite --solver gn --problem mgh01*"},
      {"verify", "verify --report " + r + " --model " + c},
      {"check", "check --preset planar-3rpr"},
      {"compare", "compare --truth " + dir / "D.truth.json" + " --model " + c + " --poses 5"},
      {"compensate", "compensate --model " + c + " --targets " + d + " --out /dev/null"},
  };
  // Commands whose result is a file of their own format, not a --json report.
  const std::map<std::string, std::string> documents = {
      {"model", "model"},
      {"export", "export --model " + c + " --format json"},
  };
  std::set<std::string> documents_absent;
#if KINCAL_WITH_VISION
  // A chessboard of 6 x 8 squares of 40 px (5 x 7 inner corners) on a white page, as a PGM.
  const std::string images = dir / "images";
  std::filesystem::create_directories(images);
  {
    std::ofstream pgm(images + "/board.pgm", std::ios::binary);
    pgm << "P5\n640 480\n255\n";
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x) {
        const int c = (x - 160) / 40, r = (y - 120) / 40;
        const bool on_board = x >= 160 && x < 480 && y >= 120 && y < 360;
        pgm.put(static_cast<char>(on_board && (r + c) % 2 == 0 ? 0 : 255));
      }
  }
  commands.emplace("detect", "detect --target chessboard:5x7:40mm --images " + images + " --out " +
                                 dir / "V.csv");
#else
  // Built without OpenCV: detect says so in one line, and writes no document.
  documents_absent.insert("detect");
  const CliResult detect = run_cli("detect --target chessboard:5x7:40mm --images . --out V.csv");
  EXPECT_EQ(detect.exit_code, 2);
  EXPECT_NE(detect.err.find("needs OpenCV"), std::string::npos) << detect.err;
#endif
  std::set<std::string> covered;
  covered.insert(documents_absent.begin(), documents_absent.end());
  // kincal run writes what its steps' commands write, each in its own format (with the
  // project recorded: tests/cli/project_run_test.cpp).
  covered.insert("run");
  for (const auto& [name, args] : commands) covered.insert(name);
  for (const auto& [name, args] : documents) covered.insert(name);
  for (const auto& command : cli::commands())
    EXPECT_EQ(covered.count(command.name), 1u) << "no case for command " << command.name;

  const auto check = [](const std::string& what, const CliResult& run) {
    ASSERT_EQ(run.exit_code, 0) << what << ": " << run.err;
    const auto json = nlohmann::json::parse(run.out, nullptr, false);
    ASSERT_TRUE(json.is_object()) << what << ": " << run.out.substr(0, 200);
    ASSERT_TRUE(json.contains("format") && json["format"].is_string()) << what;
    EXPECT_EQ(json["format"].get<std::string>().rfind("kincal-", 0), 0u) << what;
    ASSERT_TRUE(json.contains("version") && json["version"].is_number_integer()) << what;
    EXPECT_GE(json["version"].get<int>(), 1) << what;
  };
  for (const auto& [name, args] : commands) check(name, run_cli(args + " --json -"));
  for (const auto& [name, args] : documents) check(name, run_cli(args));
}

}  // namespace
}  // namespace kincal::testing
