// Designs a robot can use (issue 40): `design --within D.csv` draws the candidates in the
// range the robot was measured in, `--candidates-file` takes them as given, `--centre` around
// a configuration, an arm with joint limits within them by default, and on a freshly
// imported URDF arm (every parameter free) design keeps what the candidates determine, as
// calibrate does, instead of stopping.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "cli_runner.hpp"

namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

std::string ur5_urdf() {
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  return std::string(source ? source : ".") + "/examples/ur5-laser-tracker/ur5.urdf";
}

// The data rows (numbers) of a CSV file, comments and header skipped.
std::vector<std::vector<double>> rows_of(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::vector<double>> rows;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) row.push_back(f.empty() ? NAN : std::stod(f));
    rows.push_back(row);
  }
  return rows;
}

TEST(DesignRegion, AnImportedArmIsDesignedInsideTheMeasuredRange) {
  TempDir dir("design-region");
  ASSERT_EQ(run_cli("model --urdf " + ur5_urdf() + " --tip flange --point 0,0.09,31 --out " +
                    dir / "ur5.json")
                .exit_code,
            0);
  // Where the robot was measured: elbow between 30 and 140 degrees, the others in their own
  // ranges (a grid like the public data's).
  std::ofstream(dir / "measured.csv")
      << "shoulder_pan_joint_deg,shoulder_lift_joint_deg,elbow_joint_deg,wrist_1_joint_deg,"
         "wrist_2_joint_deg,wrist_3_joint_deg\n"
         "-60,-150,30,-180,40,-90\n"
         "60,-40,140,-20,140,90\n"
         "0,-90,90,-90,90,0\n";
  const auto r =
      run_cli("design --model " + dir / "ur5.json" + " --within " + dir / "measured.csv" +
              " --poses 40 --candidates 2000 --noise-std 0.065mm --out " + dir / "configs.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("the candidates determine"), std::string::npos) << r.err;
  const auto rows = rows_of(dir / "configs.csv");
  ASSERT_EQ(rows.size(), 40u);
  const double low[6] = {-60, -150, 30, -180, 40, -90}, high[6] = {60, -40, 140, -20, 140, 90};
  for (const auto& row : rows)
    for (int i = 0; i < 6; ++i) {
      const double deg = row[static_cast<std::size_t>(i)] * 180 / M_PI;
      EXPECT_GE(deg, low[i] - 1e-9) << i;
      EXPECT_LE(deg, high[i] + 1e-9) << i;
    }

  // Given candidates: the design is made of them.
  std::ofstream given(dir / "given.csv");
  given << "shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,wrist_2_joint,"
           "wrist_3_joint\n";
  for (int k = 0; k < 200; ++k) {
    for (int i = 0; i < 6; ++i)
      given << (i ? "," : "")
            << 0.8 * std::sin(0.37 * k + 1.1 * i) + (i == 2 ? 1.5 : 0) + (i == 1 ? -1.5 : 0);
    given << "\n";
  }
  given.close();
  const auto g =
      run_cli("design --model " + dir / "ur5.json" + " --candidates-file " + dir / "given.csv" +
              " --poses 30 --noise-std 0.065mm --out " + dir / "from-given.csv");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const auto candidates = rows_of(dir / "given.csv");
  for (const auto& row : rows_of(dir / "from-given.csv")) {
    bool found = false;
    for (const auto& c : candidates) {
      bool same = true;
      for (int i = 0; i < 6; ++i)
        same = same &&
               std::abs(c[static_cast<std::size_t>(i)] - row[static_cast<std::size_t>(i)]) < 1e-12;
      found = found || same;
    }
    EXPECT_TRUE(found);
  }
  const auto both = run_cli("design --model " + dir / "ur5.json" + " --within " +
                            dir / "measured.csv" + " --candidates-file " + dir / "given.csv" +
                            " --poses 30 --noise-std 0.065mm --out " + dir / "x.csv");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("give one of --within, --candidates-file and --centre"),
            std::string::npos)
      << both.err;
}

// Without a region, an arm whose joints all have limits is designed within them (the UR5's
// URDF: +-2 pi, the elbow +-pi), never in the old small box around zero; --centre draws
// around a configuration, the box clipped to the limits.
TEST(DesignRegion, AnArmWithLimitsIsDesignedWithinThem) {
  TempDir dir("design-limits");
  ASSERT_EQ(run_cli("model --urdf " + ur5_urdf() + " --tip flange --point 0,0.09,31 --out " +
                    dir / "ur5.json")
                .exit_code,
            0);
  const auto r = run_cli("design --model " + dir / "ur5.json" +
                         " --poses 30 --candidates 2000 --noise-std 0.065mm --out " +
                         dir / "configs.csv" + " --json " + dir / "design.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(from the joint limits;"), std::string::npos) << r.out;
  double widest = 0;
  for (const auto& row : rows_of(dir / "configs.csv"))
    for (int i = 0; i < 6; ++i) {
      const double q = row[static_cast<std::size_t>(i)];
      EXPECT_LE(std::abs(q), (i == 2 ? M_PI : 2 * M_PI) + 1e-12) << i;
      widest = std::max(widest, std::abs(q));
    }
  EXPECT_GT(widest, 1.0);  // beyond the old +-0.5 rad box around zero
  const std::string json = read_text(dir / "design.json");
  EXPECT_NE(json.find("\"region\": \"the joint limits\""), std::string::npos);

  const auto c = run_cli("design --model " + dir / "ur5.json" +
                         " --centre 0,-1.5,3,-1.5,-1.5,0 --config-range 0.5rad --poses 30 "
                         "--candidates 2000 --noise-std 0.065mm --out " +
                         dir / "centred.csv");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("(from the centre ± the actuator ranges, clipped to the joint limits;"),
            std::string::npos)
      << c.out;
  const double centre[6] = {0, -1.5, 3, -1.5, -1.5, 0};
  for (const auto& row : rows_of(dir / "centred.csv"))
    for (int i = 0; i < 6; ++i) {
      const double q = row[static_cast<std::size_t>(i)];
      EXPECT_LE(std::abs(q - centre[i]), 0.5 + 1e-12) << i;
      if (i == 2) {
        EXPECT_LE(q, M_PI + 1e-12);
      }
    }
  const auto wrong = run_cli("design --model " + dir / "ur5.json" +
                             " --centre 0,1 --poses 30 --noise-std 0.065mm --out " + dir / "x.csv");
  EXPECT_EQ(wrong.exit_code, 2);
}

}  // namespace
