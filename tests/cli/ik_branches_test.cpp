// Inverse kinematics with branches (issue 40): `ik --near` returns the solution nearest a given
// configuration, `ik --all` the distinct solutions of a 6-joint arm (a UR5 has eight).

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace {

using kincal::testing::run_cli;
using kincal::testing::TempDir;

std::vector<double> joints_of(const nlohmann::ordered_json& row) {
  std::vector<double> q;
  for (const auto& [name, value] : row["actuators"].items()) q.push_back(value.get<double>());
  return q;
}

TEST(IkBranches, NearPicksTheBranchAndAllFindsTheUr5sEight) {
  TempDir dir("ik-branches");
  ASSERT_EQ(run_cli("model --preset ur5-urdf --out " + dir / "m.json").exit_code, 0);
  const auto fk =
      run_cli("fk --model " + dir / "m.json" + " --actuators 0.3,-1.2,1.4,-1.6,-1.5,0.2 --json -");
  ASSERT_EQ(fk.exit_code, 0) << fk.err;
  const auto pose = nlohmann::ordered_json::parse(fk.out)["pose"];
  char text[200];
  std::snprintf(text, sizeof text, "--pose=%.12g,%.12g,%.12g,%.12g,%.12g,%.12g",
                pose["x_mm"].get<double>(), pose["y_mm"].get<double>(), pose["z_mm"].get<double>(),
                pose["rx_deg"].get<double>(), pose["ry_deg"].get<double>(),
                pose["rz_deg"].get<double>());
  const auto all = run_cli("ik --model " + dir / "m.json" + " " + text + " --all --json -");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const auto solutions = nlohmann::ordered_json::parse(all.out)["solutions"];
  EXPECT_EQ(solutions.size(), 8u);
  const std::vector<double> commanded = {0.3, -1.2, 1.4, -1.6, -1.5, 0.2};
  const auto first = joints_of(solutions[0]);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(first[i], commanded[i], 1e-6);
  // Every solution reaches the pose (fk of it), and --near a solution returns that one.
  for (std::size_t k = 1; k < solutions.size(); ++k) {
    const auto q = joints_of(solutions[k]);
    std::string near;
    for (double v : q) near += (near.empty() ? "" : ",") + std::to_string(v + 0.01);
    const auto one =
        run_cli("ik --model " + dir / "m.json" + " " + text + " --near=" + near + " --json -");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    const auto got = joints_of(nlohmann::ordered_json::parse(one.out));
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(std::remainder(got[i] - q[i], 2 * M_PI), 0, 1e-6) << "solution " << k;
  }
  const auto bad = run_cli("ik --model " + dir / "m.json" + " " + text + " --near 1,2");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--near"), std::string::npos) << bad.err;
}

// A start per row (issue 40): `ik --data P.csv --seeds` takes each row's start from its own
// actuator columns (unit suffixes allowed), so a table of poses with the configurations the
// robot was in comes back on the robot's branches; from home the rows land elsewhere.
TEST(IkBranches, SeedsGiveEachRowItsOwnStart) {
  TempDir dir("ik-seeds");
  ASSERT_EQ(run_cli("model --preset ur5-urdf --out " + dir / "m.json").exit_code, 0);
  // Configurations on several branches (elbow up and down, wrist flipped), in degrees.
  std::ofstream(dir / "q.csv") << "shoulder_pan_joint_deg,shoulder_lift_joint_deg,elbow_joint_deg,"
                                  "wrist_1_joint_deg,wrist_2_joint_deg,wrist_3_joint_deg\n"
                                  "20,-70,80,-90,-90,10\n"
                                  "20,-150,-80,40,-90,10\n"
                                  "-40,-60,100,-120,90,30\n"
                                  "160,-120,-60,-30,70,-20\n";
  const auto fk = run_cli("fk --model " + dir / "m.json" + " --data " + dir / "q.csv" + " --out " +
                          dir / "poses.csv");
  ASSERT_EQ(fk.exit_code, 0) << fk.err;
  // The fk table has the pose columns and, renamed with _deg, the configurations as seeds.
  std::ifstream in(dir / "poses.csv");
  std::ofstream seeded(dir / "seeded.csv");
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      for (const char* j : {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                            "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"}) {
        const std::size_t at = line.find(std::string(",") + j + ",");
        ASSERT_NE(at, std::string::npos) << line;
        line.replace(at + 1, std::string(j).size(), std::string("seed_") + j);
      }
      header = false;
    }
    seeded << line << "\n";
  }
  seeded.close();
  // Seeds in the columns the model names: the fk table itself.
  const auto with = run_cli("ik --model " + dir / "m.json" + " --data " + dir / "poses.csv" +
                            " --seeds --json -");
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const auto from_home =
      run_cli("ik --model " + dir / "m.json" + " --data " + dir / "seeded.csv" + " --json -");
  ASSERT_EQ(from_home.exit_code, 0) << from_home.err;
  const double q[4][6] = {{20, -70, 80, -90, -90, 10},
                          {20, -150, -80, 40, -90, 10},
                          {-40, -60, 100, -120, 90, 30},
                          {160, -120, -60, -30, 70, -20}};
  const auto rows = nlohmann::ordered_json::parse(with.out)["rows"];
  const auto home_rows = nlohmann::ordered_json::parse(from_home.out)["rows"];
  ASSERT_EQ(rows.size(), 4u);
  int elsewhere = 0;
  for (int r = 0; r < 4; ++r) {
    const auto seeded_q = joints_of(rows[r]), home_q = joints_of(home_rows[r]);
    double off = 0;
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(seeded_q[i], q[r][i] * M_PI / 180, 1e-7) << r << " " << i;
      off = std::max(off, std::abs(home_q[i] - q[r][i] * M_PI / 180));
    }
    elsewhere += off > 1e-3;
  }
  EXPECT_GE(elsewhere, 1);  // without the seeds some row is on another branch
  // Without --seeds the actuator columns are said to be unused, not "not an actuator".
  const auto unused = run_cli("ik --model " + dir / "m.json" + " --data " + dir / "poses.csv" +
                              " --out " + dir / "unused.csv");
  EXPECT_NE(unused.err.find("the actuator columns are not read (--seeds starts each row from "
                            "them)"),
            std::string::npos)
      << unused.err;
  EXPECT_EQ(unused.err.find("ignoring column 'elbow_joint'"), std::string::npos) << unused.err;
  const auto both = run_cli("ik --model " + dir / "m.json" + " --data " + dir / "poses.csv" +
                            " --seeds --near 0,0,0,0,0,0");
  EXPECT_EQ(both.exit_code, 2);
}

}  // namespace
