// Real-arm data through the binary (issue 20 items 3, 5, 6, 9): joint angles in degrees are
// an error before solving and calibrate to the same result with _deg columns; fk refuses
// bare degrees; validate reports the 3-D position error before and after and validates a
// nominal model without reading_std; calibrate reports the registration-only baseline and
// --folds cross-validation; no home_pose warning on a serial arm.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/framework/base/angles.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The CSV with its first `columns` columns (the joints) in degrees, named with `suffix`.
std::string in_degrees(const std::string& csv, int columns, const std::string& suffix) {
  std::istringstream in(csv);
  std::ostringstream out;
  out.precision(17);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    for (int c = 0; c < static_cast<int>(fields.size()); ++c) {
      if (c) out << ",";
      if (c >= columns)
        out << fields[c];
      else if (header)
        out << fields[c] << suffix;
      else
        out << std::stod(fields[c]) * 180 / kPi;
    }
    out << "\n";
    header = false;
  }
  return out.str();
}

// The rows [first, last) of a CSV (header kept).
std::string rows(const std::string& csv, int first, int last) {
  std::istringstream in(csv);
  std::string line, out;
  int row = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (row < 0 || (row >= first && row < last)) out += line + "\n";
    ++row;
  }
  return out;
}

class CliArmData : public ::testing::Test {
 protected:
  // The PUMA 560 with its laser tracker: 100 simulated configurations (seed 8), 80 to
  // calibrate and 20 held out, joint columns in rad.
  static void SetUpTestSuite() {
    dir_ = new TempDir("arm-data");
    ASSERT_EQ(run_cli("model --preset puma560 --out " + path("M.json")).exit_code, 0);
    const auto sim =
        run_cli("simulate --model " + path("M.json") +
                " --poses 100 --noise-half-width 0.01 --param-error 1mm,0.003rad --seed 8 "
                "--validation 1 --write-data " +
                path("all.csv"));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const std::string all = read_text(path("all.csv"));
    write(path("D.csv"), rows(all, 0, 80));
    write(path("H.csv"), rows(all, 80, 100));
    write(path("D_deg.csv"), in_degrees(rows(all, 0, 80), 6, "_deg"));
    write(path("D_bare.csv"), in_degrees(rows(all, 0, 80), 6, ""));
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string path(const std::string& file) { return *dir_ / file; }
  static TempDir* dir_;
};
TempDir* CliArmData::dir_ = nullptr;

TEST_F(CliArmData, DegreesWithoutSuffixAreAnErrorBeforeSolvingAndNothingIsWritten) {
  const std::string out = path("bare_out.json"), report = path("bare_report.json");
  const auto r = run_cli("calibrate --model " + path("M.json") + " --data " + path("D_bare.csv") +
                         " --out " + out + " --json " + report);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("looks like degrees"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("joint1_deg"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(report));
  for (const char* command : {"validate", "observability"}) {
    const auto v = run_cli(std::string(command) + " --model " + path("M.json") + " --data " +
                           path("D_bare.csv"));
    EXPECT_EQ(v.exit_code, 2) << command;
    EXPECT_NE(v.err.find("looks like degrees"), std::string::npos) << command << ": " << v.err;
  }
}

TEST_F(CliArmData, DegreeColumnsCalibrateToTheSameResultAsRadians) {
  const std::string rad = path("rad.json"), deg = path("deg.json");
  const auto a = run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") +
                         " --json " + rad);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run_cli("calibrate --model " + path("M.json") + " --data " + path("D_deg.csv") +
                         " --json " + deg);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const Json ra = Json::parse(read_text(rad)), rb = Json::parse(read_text(deg));
  ASSERT_EQ(ra["parameters"].size(), rb["parameters"].size());
  // Degrees written to 17 digits convert back to the radians within an ulp or two; the fit
  // moves by far less than its own uncertainty (measured: under 1e-6 of a std).
  for (std::size_t i = 0; i < ra["parameters"].size(); ++i)
    EXPECT_NEAR(ra["parameters"][i]["estimate"].get<double>(),
                rb["parameters"][i]["estimate"].get<double>(),
                1e-4 * ra["parameters"][i]["std"].get<double>())
        << ra["parameters"][i]["name"];
  // A serial arm's forward kinematics has one answer: no home_pose warning.
  EXPECT_EQ(a.err.find("home_pose"), std::string::npos) << a.err;
  EXPECT_TRUE(ra["warnings"].empty());
}

TEST_F(CliArmData, FkRefusesBareDegreesAndTakesUnits) {
  const auto bare = run_cli("fk --model " + path("M.json") + " --actuators 0,-90,90,0,0,0");
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("looks like degrees"), std::string::npos) << bare.err;
  const auto deg = run_cli("fk --model " + path("M.json") + " --actuators 0,-90deg,90deg,0,0,0");
  const auto rad = run_cli("fk --model " + path("M.json") +
                           " --actuators=0,-1.5707963267948966,1.5707963267948966,0,0,0");
  ASSERT_EQ(deg.exit_code, 0) << deg.err;
  EXPECT_EQ(deg.out, rad.out);
  const auto wrong = run_cli("fk --model " + path("M.json") + " --actuators 0,-90mm,90,0,0,0");
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("an angle"), std::string::npos) << wrong.err;
  const auto ik = run_cli("ik --model " + path("M.json") + " --pose=600,150,400,0,90,0");
  if (ik.exit_code == 0) {
    EXPECT_NE(ik.out.find("joint1 rad"), std::string::npos) << ik.out;
  }
}

TEST_F(CliArmData, ValidateReportsThePositionErrorBeforeAndAfter) {
  const std::string report = path("R.json"), calibrated = path("C.json");
  const auto c = run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") +
                         " --json " + report + " --out " + calibrated + " --folds 4");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("registration only"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("held out, 4-fold"), std::string::npos) << c.out;
  const Json r = Json::parse(read_text(report));
  const Json& p = r["position_error_mm"];
  const double before = p["before"]["mean"], after = p["after"]["mean"];
  const double registration = p["registration_only"]["mean"];
  EXPECT_GT(before, registration);
  EXPECT_GT(registration, after);
  EXPECT_TRUE(r["registration_only"]["computed"].get<bool>());
  EXPECT_EQ(r["registration_only"]["parameters"].size(), 9u);
  EXPECT_EQ(r["cross_validation"]["folds"], 4);
  EXPECT_GT(r["cross_validation"]["position_error_mm"]["mean"].get<double>(), after);
  EXPECT_GT(r["predicted_point_error_mm"]["mean_1sigma"].get<double>(), 0);
  EXPECT_EQ(r["predicted_point_error_mm"]["before_measured"]["mean"].get<double>(), before);

  // After with the report: before from its nominal values, the same as --before M.json.
  const std::string v1 = path("V1.json"), v2 = path("V2.json"), html = path("V1.html");
  const auto a = run_cli("validate --model " + calibrated + " --data " + path("H.csv") +
                         " --report " + report + " --json " + v1 + " --html " + html);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run_cli("validate --model " + calibrated + " --data " + path("H.csv") +
                         " --before " + path("M.json") + " --json " + v2);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const Json j1 = Json::parse(read_text(v1)), j2 = Json::parse(read_text(v2));
  EXPECT_EQ(j1["pose_accuracy_shown"], true);  // a tracker measures the point
  EXPECT_TRUE(j1["pose_accuracy_note"].is_null());
  EXPECT_EQ(a.out.find("measure no point"), std::string::npos) << a.out;
  for (const char* which : {"mean", "rms", "max"}) {
    EXPECT_GT(j1["position_error_mm"]["before"][which].get<double>(),
              5 * j1["position_error_mm"]["after"][which].get<double>());
    EXPECT_NEAR(j1["position_error_mm"]["before"][which].get<double>(),
                j2["position_error_mm"]["before"][which].get<double>(), 1e-12);
  }
  EXPECT_EQ(j1["position_error_mm"]["after"]["points"], 20);
  EXPECT_TRUE(j1["residuals"][0].contains("position_error_mm"));
  EXPECT_NE(read_text(html).find("3-D position error"), std::string::npos);
  EXPECT_NE(a.out.find("before  mean"), std::string::npos) << a.out;

  // The nominal model states no reading_std: validated all the same, without the test.
  const std::string v3 = path("V3.json");
  const auto n =
      run_cli("validate --model " + path("M.json") + " --data " + path("H.csv") + " --json " + v3);
  ASSERT_EQ(n.exit_code, 0) << n.err;
  const Json j3 = Json::parse(read_text(v3));
  EXPECT_EQ(j3["verdict"], "not_tested");
  EXPECT_TRUE(j3["chi_square"].is_null());
  EXPECT_NEAR(j3["position_error_mm"]["after"]["mean"].get<double>(),
              j1["position_error_mm"]["before"]["mean"].get<double>(), 1e-9);

  // --before with other parameters, --folds 1: one line, exit 2.
  const auto hexapod = run_cli("model --preset cube-hexapod --out " + path("hex.json"));
  ASSERT_EQ(hexapod.exit_code, 0);
  const auto other = run_cli("validate --model " + calibrated + " --data " + path("H.csv") +
                             " --before " + path("hex.json"));
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("not the same parameters"), std::string::npos) << other.err;
  const auto one =
      run_cli("calibrate --model " + path("M.json") + " --data " + path("D.csv") + " --folds 1");
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_NE(one.err.find("--folds"), std::string::npos) << one.err;
}

// A known distance between two sockets counts in observability as in calibrate: one more
// row in the identification Jacobian (docs/fixtures.md).
TEST(CliObservability, AFixtureDistanceIsARowOfTheIdentificationJacobian) {
  TempDir dir("observability-constraint");
  const std::string plain = dir / "plain.json", constrained = dir / "constrained.json";
  ASSERT_EQ(run_cli("model --preset ur5-urdf-socket --out " + plain).exit_code, 0);
  Json model = Json::parse(read_text(plain));
  model["sensors"] =
      Json::array({{{"type", "socket"}, {"name", "s0"}, {"point", {-400.0, -100.0, 300.0}}},
                   {{"type", "socket"}, {"name", "s1"}, {"point", {-400.0, -50.0, 300.0}}}});
  model["free"] = {"s0.point.x", "s0.point.y", "s0.point.z",          "s1.point.x",
                   "s1.point.y", "s1.point.z", "elbow_joint.origin.x"};
  std::ofstream(plain) << model.dump(2);
  model["constraints"] = Json::array(
      {{{"type", "fixture-distance"}, {"between", {"s0", "s1"}}, {"distance", 50}, {"std", 0.05}}});
  std::ofstream(constrained) << model.dump(2);
  const auto without = run_cli("observability --model " + plain + " --poses 20 --seed 3 --json -");
  const auto with =
      run_cli("observability --model " + constrained + " --poses 20 --seed 3 --json -");
  ASSERT_EQ(without.exit_code, 0) << without.err;
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const Json a = Json::parse(without.out), b = Json::parse(with.out);
  EXPECT_EQ(b["residuals"].get<int>(), a["residuals"].get<int>() + 1);
  EXPECT_EQ(b["parameters"], 7);

  // Measured data where each configuration has the ball in one socket: the other socket's
  // readings are missing and count as nothing, in observability as in calibrate's report.
  const std::string data = dir / "d.csv", half = dir / "half.csv";
  ASSERT_EQ(run_cli("simulate --model " + constrained + " --poses 20 --seed 3 --write-data " + data)
                .exit_code,
            0);
  std::istringstream in(read_text(data));
  std::ofstream out(half);
  int row = 0;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && (line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0])))) {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string f; std::getline(cells, f, ',');) fields.push_back(f);
    ASSERT_EQ(fields.size(), 12u) << line;             // 6 joints, s0.x..z, s1.x..z
    const std::size_t blank = row++ % 2 == 0 ? 9 : 6;  // s1 in even rows, s0 in odd ones
    for (std::size_t i = blank; i < blank + 3; ++i) fields[i].clear();
    for (std::size_t i = 0; i < fields.size(); ++i) out << (i ? "," : "") << fields[i];
    out << "\n";
  }
  out.close();
  const auto observed =
      run_cli("observability --model " + constrained + " --data " + half + " --json -");
  ASSERT_EQ(observed.exit_code, 0) << observed.err;
  EXPECT_EQ(Json::parse(observed.out)["residuals"], 20 * 3 + 1);
  const auto calibrated =
      run_cli("calibrate --model " + constrained + " --data " + half + " --json " + dir / "r.json");
  ASSERT_EQ(calibrated.exit_code, 0) << calibrated.err;
  EXPECT_EQ(Json::parse(read_text(dir / "r.json"))["identifiability"]["residuals"], 20 * 3 + 1);
}

}  // namespace
}  // namespace kincal
