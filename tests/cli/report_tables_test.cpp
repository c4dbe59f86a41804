// The tables of a calibration report stay aligned with long names (issue 40: an imported
// arm's run printed 38 notes and 38 "fixed" lines, and names beyond 22 characters pushed
// their rows out of the parameter table): one note for the fixed parameters on stderr, one
// aligned table of them, with what each duplicates, in the report.

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <vector>

#include "cli_runner.hpp"

namespace {

using kincal::testing::run_cli;
using kincal::testing::TempDir;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) lines.push_back(line);
  return lines;
}

TEST(ReportTables, AnImportedArmsFixedParametersAreOneAlignedTable) {
  TempDir dir("report-tables");
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  const std::string urdf =
      std::string(source ? source : ".") + "/examples/ur5-laser-tracker/ur5.urdf";
  ASSERT_EQ(run_cli("model --urdf " + urdf + " --tip flange --out " + dir / "ur5.json").exit_code,
            0);
  const auto simulated = run_cli("simulate --model " + dir / "ur5.json" +
                                 " --poses 60 --seed 3 --write-data " + dir / "D.csv");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const auto run = run_cli("calibrate --model " + dir / "ur5.json" + " --data " + dir / "D.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // stderr: one note about the fixed parameters, not one per parameter.
  int notes = 0;
  for (const std::string& line : lines_of(run.err))
    if (line.find("fixed at their model values") != std::string::npos) ++notes;
  EXPECT_EQ(notes, 1) << run.err;
  EXPECT_EQ(run.err.find("moves the readings as"), std::string::npos) << run.err;

  // stdout: the fixed table, every column starting where its header's does.
  const std::vector<std::string> out = lines_of(run.out);
  std::size_t header = 0;
  while (header < out.size() && out[header].rfind("  parameter ", 0) != 0) ++header;
  ASSERT_LT(header, out.size()) << run.out;
  const std::size_t words = out[header].find("in words"),
                    effect = out[header].find("what the data see of it");
  int rows = 0;
  for (std::size_t i = header + 1; i < out.size() && out[i].rfind("  ", 0) == 0; ++i, ++rows) {
    EXPECT_EQ(out[i][words - 1], ' ') << out[i];
    EXPECT_NE(out[i][words], ' ') << out[i];
    EXPECT_NE(out[i][effect], ' ') << out[i];
    EXPECT_EQ(out[i].compare(0, 2, "  "), 0);
  }
  EXPECT_GE(rows, 30);
  // The parameter table: the unit column where its header's is, whatever the name's length.
  std::size_t params = 0;
  while (params < out.size() && out[params] != "parameters:") ++params;
  ASSERT_LT(params + 1, out.size());
  const std::size_t unit = out[params + 1].find("unit");
  for (std::size_t i = params + 2; i < out.size() && out[i].rfind("  ", 0) == 0; ++i) {
    const std::string u = out[i].substr(unit, 3);
    EXPECT_TRUE(u == "mm " || u == "rad") << out[i];
  }
}

}  // namespace
