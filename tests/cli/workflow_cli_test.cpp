// The set-up pitfalls through the real binary: a home_pose far from the data is a note and a
// report warning, encoder strokes get a hint about leg offsets, and observability
// --sensitivity prints and writes the fixed-parameter table.

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

class CliWorkflow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_cli("model --out " + m_).exit_code, 0);
    ASSERT_EQ(run_cli("simulate --model " + m_ + " --case 5 --seed 7 --write-data " + d_).exit_code,
              0);
  }
  TempDir dir_{"workflow"};
  std::string m_ = dir_ / "nominal.json", d_ = dir_ / "measured.csv";
};

TEST_F(CliWorkflow, AHomePoseFarFromTheDataIsANoteAndAReportWarning) {
  const auto clean =
      run_cli("calibrate --model " + m_ + " --data " + d_ + " --json " + (dir_ / "clean.json"));
  ASSERT_EQ(clean.exit_code, 0) << clean.err;
  EXPECT_EQ(clean.err.find("home_pose"), std::string::npos) << clean.err;
  EXPECT_TRUE(Json::parse(read_text(dir_ / "clean.json"))["warnings"].empty());

  Json model = Json::parse(read_text(m_));
  model["mechanism"]["home_pose"]["position"] = {0, 0, 510};
  std::ofstream(dir_ / "wrong.json") << model.dump(2);
  const auto wrong = run_cli("calibrate --model " + (dir_ / "wrong.json") + " --data " + d_ +
                             " --report " + (dir_ / "wrong-report.json"));
  ASSERT_EQ(wrong.exit_code, 0) << wrong.err;
  EXPECT_NE(wrong.err.find("note: forward kinematics of the data lands far from the model's "
                           "home_pose"),
            std::string::npos)
      << wrong.err;
  const Json report = Json::parse(read_text(dir_ / "wrong-report.json"));
  ASSERT_EQ(report["warnings"].size(), 1u);
  EXPECT_NE(report["warnings"][0].get<std::string>().find("home_pose"), std::string::npos);
}

TEST_F(CliWorkflow, EncoderStrokesGetAHintAboutLegOffsets) {
  // The same data as strokes from a zero 20 mm below each leg's home length.
  const auto ik = run_cli("ik --model " + m_ + " --pose 0,0,410,0,0,0");
  ASSERT_EQ(ik.exit_code, 0) << ik.err;
  std::istringstream ik_lines(ik.out);
  std::vector<double> home;
  std::string name;
  double value;
  while (ik_lines >> name >> value) home.push_back(value);
  ASSERT_GE(home.size(), 6u);
  std::istringstream in(read_text(d_));
  std::ofstream out(dir_ / "strokes.csv");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'l') {
      out << line << "\n";
      continue;
    }
    std::stringstream fields(line);
    std::string field;
    for (int c = 0; std::getline(fields, field, ','); ++c)
      out << (c ? "," : "") << (c < 6 ? std::stod(field) - (home[c] - 20) : std::stod(field));
    out << "\n";
  }
  out.close();
  const auto r = run_cli("calibrate --model " + m_ + " --data " + (dir_ / "strokes.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("hint: the actuator values look like encoder strokes"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("offset"), std::string::npos);
  // Real lengths that fail get no such hint.
  EXPECT_EQ(run_cli("calibrate --model " + m_ + " --data " + d_).err.find("encoder strokes"),
            std::string::npos);
}

TEST_F(CliWorkflow, ObservabilitySensitivityListsEveryFixedParameter) {
  const auto r = run_cli("observability --model " + m_ + " --poses 60 --sensitivity --json " +
                         (dir_ / "s.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("sensitivity to fixed parameters"), std::string::npos) << r.out;
  const Json j = Json::parse(read_text(dir_ / "s.json"));
  ASSERT_TRUE(j.contains("sensitivity"));
  // The cube hexapod has 49 parameters, 24 free.
  EXPECT_EQ(j["sensitivity"].size(), 25u);
  for (const auto& row : j["sensitivity"]) {
    EXPECT_EQ(row["error"].get<double>(), 1.0) << row["name"];
    EXPECT_GE(row["position_max_mm"].get<double>(), row["position_mean_mm"].get<double>());
  }
  // The gauge's base point, 1 mm off along z, moves the whole machine by 1 mm and leaves the
  // residuals unchanged: invisible in the data, visible in the pose.
  for (const auto& row : j["sensitivity"])
    if (row["name"] == "gauge.base.z") {
      EXPECT_LT(row["residual_rms"].get<double>(), 1e-9);
      EXPECT_NEAR(row["position_mean_mm"].get<double>(), 1.0, 1e-6);
    }
  const auto bad = run_cli("observability --model " + m_ +
                           " --poses 60 --sensitivity --sensitivity-step 1furlong");
  EXPECT_EQ(bad.exit_code, 2);
}

}  // namespace
}  // namespace kincal
