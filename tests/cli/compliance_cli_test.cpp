// Joint compliance and corrected targets through the program: `kincal model --urdf
// --compliance` and its refusals; the calibration report's line on what a URDF alone leaves
// uncorrected (and its figure against `kincal fk` of the model with the compliance removed);
// the URDF export's note; `kincal compensate` and its refusals.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

std::string ur5_urdf() {
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  return std::string(source ? source : ".") + "/examples/ur5-laser-tracker/ur5.urdf";
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The value of `column` in each data row of a CSV table.
std::vector<double> column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> header;
  std::vector<double> out;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    if (header.empty()) {
      header = fields;
      continue;
    }
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name && i < fields.size() && !fields[i].empty())
        out.push_back(std::stod(fields[i]));
  }
  return out;
}

TEST(ComplianceCli, ModelFromUrdfWithComplianceAndItsRefusals) {
  TempDir dir("compliance-model");
  const auto ok =
      run_cli("model --urdf " + ur5_urdf() + " --tip flange --compliance --out " + dir / "m.json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const Json m = Json::parse(read_text(dir / "m.json"));
  EXPECT_EQ(m["mechanism"]["compliance"]["masses"], "given");
  EXPECT_EQ(m["mechanism"]["compliance"]["masses_source"], "URDF inertials");
  EXPECT_EQ(m["mechanism"]["compliance"]["links"].size(), 6u);

  const auto fitted = run_cli("model --urdf " + ur5_urdf() +
                              " --tip flange --compliance fitted --payload-column --out -");
  ASSERT_EQ(fitted.exit_code, 0) << fitted.err;
  EXPECT_NE(fitted.out.find("\"shoulder_lift_joint.moment.elbow_joint\""), std::string::npos);
  EXPECT_NE(fitted.out.find("\"column\": true"), std::string::npos);

  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {" --tip flange --payload-column", "--payload-column needs --compliance"},
           {" --tip flange --compliance stiff", "--compliance 'stiff': expected urdf, fitted"},
           {" --tip flange --payload-centre 0,0", "--payload-centre"}}) {
    const auto bad = run_cli("model --urdf " + ur5_urdf() + args + " --out " + dir / "x.json");
    EXPECT_EQ(bad.exit_code, 2) << args;
    EXPECT_NE(bad.err.find(says), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  }
  const auto preset = run_cli("model --preset cube-hexapod --compliance --out -");
  EXPECT_EQ(preset.exit_code, 2);
  EXPECT_NE(preset.err.find("--compliance needs --urdf"), std::string::npos) << preset.err;
}

TEST(ComplianceCli, TheReportSaysWhatTheUrdfAloneLeavesUncorrected) {
  TempDir dir("compliance-report");
  ASSERT_EQ(run_cli("model --preset ur5-urdf-compliance --out " + dir / "m.json").exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + dir / "m.json" + " --poses 40 --seed 3 --write-data " +
                    dir / "data.csv")
                .exit_code,
            0);
  const auto cal = run_cli("calibrate --model " + dir / "m.json" + " --data " + dir / "data.csv" +
                           " --out " + dir / "cal.json" + " --json " + dir / "report.json");
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  EXPECT_NE(cal.out.find("a kinematic export (URDF, DH) holds the geometry only"),
            std::string::npos)
      << cal.out;
  const Json report = Json::parse(read_text(dir / "report.json"));
  ASSERT_TRUE(report.contains("geometry_only_export"));
  const double mean = report["geometry_only_export"]["mean"];
  EXPECT_GT(mean, 0.01);

  // The same figure from the program's forward kinematics of the calibrated model with its
  // compliance zeroed.
  Json geometry = Json::parse(read_text(dir / "cal.json"));
  geometry["mechanism"]["compliance"]["values"] = Json::object();
  write(dir / "geometry.json", geometry.dump(2));
  const auto with =
      run_cli("fk --model " + dir / "cal.json" + " --data " + dir / "data.csv" + " --out -");
  const auto without =
      run_cli("fk --model " + dir / "geometry.json" + " --data " + dir / "data.csv" + " --out -");
  ASSERT_EQ(with.exit_code, 0) << with.err;
  ASSERT_EQ(without.exit_code, 0) << without.err;
  double sum = 0;
  const auto x1 = column(with.out, "tracker.x"), y1 = column(with.out, "tracker.y"),
             z1 = column(with.out, "tracker.z");
  const auto x0 = column(without.out, "tracker.x"), y0 = column(without.out, "tracker.y"),
             z0 = column(without.out, "tracker.z");
  ASSERT_EQ(x1.size(), 40u);
  for (std::size_t i = 0; i < x1.size(); ++i)
    sum += std::sqrt(std::pow(x1[i] - x0[i], 2) + std::pow(y1[i] - y0[i], 2) +
                     std::pow(z1[i] - z0[i], 2));
  EXPECT_NEAR(sum / 40, mean, 1e-9 * (1 + mean));

  // The exported URDF says so too; a model without compliance has neither line.
  const auto urdf = run_cli("export --model " + dir / "cal.json" + " --format urdf --out -");
  ASSERT_EQ(urdf.exit_code, 0) << urdf.err;
  EXPECT_NE(urdf.out.find("It holds the geometry only"), std::string::npos);
  ASSERT_EQ(run_cli("model --preset ur5-urdf --out " + dir / "rigid.json").exit_code, 0);
  ASSERT_EQ(run_cli("simulate --model " + dir / "rigid.json" + " --poses 40 --write-data " +
                    dir / "rigid.csv")
                .exit_code,
            0);
  const auto rigid = run_cli("calibrate --model " + dir / "rigid.json" + " --data " +
                             dir / "rigid.csv" + " --out " + dir / "rigid-cal.json");
  ASSERT_EQ(rigid.exit_code, 0) << rigid.err;
  EXPECT_EQ(rigid.out.find("holds the geometry only"), std::string::npos);
}

TEST(ComplianceCli, CompensateWritesCommandsAndRefusesBadTargets) {
  TempDir dir("compensate");
  ASSERT_EQ(run_cli("model --preset ur5-urdf-compliance --out " + dir / "m.json").exit_code, 0);
  // Two rows: a reachable point near the arm's home (no commands: the start is home) and one
  // 5 m away.
  write(dir / "targets.csv", "tracker.x,tracker.y,tracker.z\n100,-300,400\n5000,0,0\n");
  const auto r =
      run_cli("compensate --model " + dir / "m.json" + " --targets " + dir / "targets.csv" +
              " --payload 1.5 --out " + dir / "out.csv" + " --json " + dir / "summary.json");
  EXPECT_EQ(r.exit_code, 1) << r.err;  // a row failed
  EXPECT_NE(r.out.find("2 targets (the file's reading columns): 1 solved, 1 failed"),
            std::string::npos)
      << r.out;
  const std::string out = read_text(dir / "out.csv");
  EXPECT_EQ(column(out, "payload"), std::vector<double>({1.5}));
  EXPECT_NE(out.find(",unreachable,"), std::string::npos) << out;
  const auto error = column(out, "error");
  ASSERT_EQ(error.size(), 1u);
  EXPECT_LT(error[0], 1e-9);
  const Json summary = Json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(summary["format"], "kincal-compensate");
  EXPECT_EQ(summary["failed"], 1);

  // The commands solved, by the program's forward kinematics: the wanted point.
  const auto predicted_x = column(out, "predicted.tracker.x");
  ASSERT_EQ(predicted_x.size(), 1u);
  EXPECT_NEAR(predicted_x[0], 100, 1e-9);

  write(dir / "partial.csv", "shoulder_pan_joint,tracker.x,tracker.y,tracker.z\n0,1,2,3\n");
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {" --targets " + dir / "partial.csv", "1 of the 6 commanded actuator columns"},
           {" --targets " + dir / "targets.csv" + " --near 1,2", "--near"},
           {" --targets " + dir / "targets.csv" + " --out " + dir / "targets.csv", "--targets"},
           {"", "--targets FILE is required"}}) {
    const std::string out_arg =
        args.find(" --out ") == std::string::npos ? " --out " + dir / "o.csv" : std::string();
    const auto bad = run_cli("compensate --model " + dir / "m.json" + args + out_arg);
    EXPECT_EQ(bad.exit_code, 2) << args << bad.err;
    EXPECT_NE(bad.err.find(says), std::string::npos) << bad.err;
  }
  EXPECT_EQ(read_text(dir / "targets.csv"),
            "tracker.x,tracker.y,tracker.z\n100,-300,400\n5000,0,0\n");
  ASSERT_EQ(run_cli("model --preset ur5-urdf --out " + dir / "rigid.json").exit_code, 0);
  const auto no_payload = run_cli("compensate --model " + dir / "rigid.json" + " --targets " +
                                  dir / "targets.csv" + " --payload 1 --out " + dir / "o.csv");
  EXPECT_EQ(no_payload.exit_code, 2);
  EXPECT_NE(no_payload.err.find("--payload: the model has no payload column"), std::string::npos)
      << no_payload.err;
}

}  // namespace
