// fk and ik as workflows (framework/workflows/kinematics_table.hpp): values given as text with
// units, a table read from a file with its notes and line numbers, ik seeded per row.

#include "kincal/framework/workflows/kinematics_table.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(KinematicsTable, ValuesAsTextTakeTheirUnits) {
  const auto model = make_preset("ur5");
  const KinematicsRow in_degrees = forward_at(*model, "0,-90deg,90deg,0,90deg,0", "--actuators");
  const KinematicsRow in_radians =
      forward_at(*model, "0,-1.5707963267948966,1.5707963267948966,0,1.5707963267948966,0", "q");
  ASSERT_TRUE(in_degrees.ok());
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(in_degrees.pose[static_cast<std::size_t>(k)],
                in_radians.pose[static_cast<std::size_t>(k)], 1e-9);
  EXPECT_EQ(message_of([&] { forward_at(*model, "0,-90,90,0,90,0", "--actuators"); }),
            "--actuators '0,-90,90,0,90,0': joint2 = -90 is beyond one turn, which looks like "
            "degrees; revolute joints take radians: write -90deg (a unit after each value: deg, "
            "rad, mm, m) or give radians");
  EXPECT_EQ(message_of([&] { parse_pose_values("1,2,x", "pose"); }),
            "pose '1,2,x': field 3 'x' is not a finite number (expected x,y,z in mm and rx,ry,rz "
            "in degrees)");
  EXPECT_NE(message_of([&] {
              inverse_at(*model, "0,0,9000,0,0,0", "pose", nullptr);
            }).find("expected a pose the model can reach"),
            std::string::npos);
  // ik at fk's pose, from a start near the configuration, finds the configuration again.
  const std::string pose =
      std::to_string(in_degrees.pose[0]) + "," + std::to_string(in_degrees.pose[1]) + "," +
      std::to_string(in_degrees.pose[2]) + "," + std::to_string(in_degrees.pose[3]) + "," +
      std::to_string(in_degrees.pose[4]) + "," + std::to_string(in_degrees.pose[5]);
  VectorXd near(6);
  near << 0.1, -1.5, 1.5, 0.1, 1.5, 0.1;
  const KinematicsRow back = inverse_at(*model, pose, "pose", &near);
  ASSERT_TRUE(back.ok()) << back.reason;
  EXPECT_NEAR(back.actuators[1], -M_PI / 2, 1e-5);
  EXPECT_GE(inverse_solutions_at(*model, pose, "pose", &near).size(), 2u);
}

TEST(KinematicsTable, ATableIsARowPerLineWithItsNotes) {
  const auto model = make_preset("ur5");
  const auto dir = std::filesystem::temp_directory_path() /
                   ("kincal-kinematics-table-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string configurations = (dir / "q.csv").string();
  std::ofstream(configurations) << "joint1_deg,joint2_deg,joint3_deg,joint4_deg,joint5_deg,"
                                   "joint6_deg,comment\n0,-90,90,0,90,0,a\n\n10,-80,70,-30,80,"
                                   "20,b\n";
  KinematicsTableRequest forward;
  forward.data_file = configurations;
  const KinematicsTable poses = kinematics_table(*model, forward);
  ASSERT_EQ(poses.rows.size(), 2u);
  EXPECT_EQ(poses.failures, 0);
  EXPECT_EQ(poses.rows[0].line, 2);
  EXPECT_EQ(poses.rows[1].line, 4);
  ASSERT_EQ(poses.notes.size(), 1u);
  EXPECT_NE(poses.notes[0].find("ignoring column 'comment'"), std::string::npos);

  // The poses with their configurations as seeds: each row finds its own configuration.
  const std::string table = (dir / "poses.csv").string();
  std::ofstream(table) << rows_csv(*model, poses.rows);
  KinematicsTableRequest inverse;
  inverse.inverse = true;
  inverse.seeds = true;
  inverse.data_file = table;
  const KinematicsTable back = kinematics_table(*model, inverse);
  ASSERT_EQ(back.rows.size(), 2u);
  for (std::size_t r = 0; r < 2; ++r) {
    ASSERT_TRUE(back.rows[r].ok()) << back.rows[r].reason;
    EXPECT_LT((back.rows[r].actuators - poses.rows[r].actuators).norm(), 1e-6);
  }
  // Without seeds the actuator columns are not read, and a note says so.
  inverse.seeds = false;
  const KinematicsTable unseeded = kinematics_table(*model, inverse);
  EXPECT_NE(std::find_if(unseeded.notes.begin(), unseeded.notes.end(),
                         [](const std::string& n) {
                           return n.find("the actuator columns are not read (--seeds") !=
                                  std::string::npos;
                         }),
            unseeded.notes.end());
  inverse.seeds = true;
  inverse.near = VectorXd::Zero(6);
  EXPECT_EQ(message_of([&] { kinematics_table(*model, inverse); }), "give near or seeds, not both");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace kincal
