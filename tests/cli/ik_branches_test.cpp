// Inverse kinematics with branches (issue 40): `ik --near` returns the solution nearest a given
// configuration, `ik --all` the distinct solutions of a 6-joint arm (a UR5 has eight).

#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
