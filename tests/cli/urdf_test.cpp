// A robot from its URDF through kincal and back: `model --urdf` (joint names as columns, limits,
// a base link below the root, fixed joints between moving ones), `calibrate` choosing the
// identifiable parameters itself and naming what it fixed, an explicit rank-deficient mask
// stopping with the null directions, and `export --format urdf` writing the user's own URDF
// (meshes, inertials, comments, unknown tags kept) whose world -> tcp chain, read back by
// urdfdom and multiplied out here (not by kincal's model code), gives the calibrated model's
// predictions at every measured configuration within 1e-6 mm; check_urdf accepts it.

#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

// A stand (the URDF's root) under the arm's base, a fixed bracket between two moving joints
// whose axes are parallel, a prismatic joint, a skewed axis, and the tip behind a fixed
// joint; a mesh, an inertial, a comment and a Gazebo tag that the export must keep.
const char* kRobot = R"(<?xml version="1.0"?>
<robot name="testbot">
  <!-- a comment the export keeps -->
  <link name="stand"/>
  <joint name="stand_joint" type="fixed">
    <parent link="stand"/><child link="base_link"/>
    <origin xyz="0.1 0.2 0.3" rpy="0 0 0.5"/>
  </joint>
  <link name="base_link">
    <visual><geometry><mesh filename="package://testbot/meshes/base.stl"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l1">
    <inertial><mass value="2.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.05 0.1" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <link name="l2"/>
  <joint name="bracket" type="fixed">
    <parent link="l2"/><child link="l2b"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/>
  </joint>
  <link name="l2b"/>
  <joint name="j3" type="revolute">
    <parent link="l2b"/><child link="l3"/>
    <origin xyz="0 -0.05 0.2" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/>
  </joint>
  <link name="l3"/>
  <joint name="j4" type="prismatic">
    <parent link="l3"/><child link="l4"/>
    <origin xyz="0.05 0 0.05" rpy="0 0.3 0"/><axis xyz="0 0 1"/>
    <limit lower="-0.05" upper="0.1" effort="10" velocity="1"/>
  </joint>
  <link name="l4"/>
  <joint name="j5" type="continuous">
    <parent link="l4"/><child link="l5"/>
    <origin xyz="0 0 0.08" rpy="0.2 0 0"/><axis xyz="1 0.2 0"/>
  </joint>
  <link name="l5"/>
  <joint name="j6" type="revolute">
    <parent link="l5"/><child link="l6"/>
    <origin xyz="0.06 0 0" rpy="0 1.5707963267948966 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l6"/>
  <joint name="mount" type="fixed">
    <parent link="l6"/><child link="tool_mount"/>
    <origin xyz="0 0 0.03" rpy="0 0 0"/>
  </joint>
  <link name="tool_mount"/>
  <gazebo reference="l1"><material>Gazebo/Grey</material></gazebo>
</robot>
)";

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// World -> tcp of a URDF as urdfdom reads it: the product of the joints' origins and motions
// from tcp up to the root, by joint name. Independent of kincal's models.
Eigen::Isometry3d urdf_world_to_tcp(const urdf::ModelInterface& robot,
                                    const std::map<std::string, double>& q) {
  auto iso = [](const urdf::Pose& p) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
    T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                     .toRotationMatrix();
    return T;
  };
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (urdf::LinkConstSharedPtr link = robot.getLink("tcp"); link->parent_joint;
       link = robot.getLink(link->parent_joint->parent_link_name)) {
    const urdf::Joint& j = *link->parent_joint;
    Eigen::Isometry3d step = iso(j.parent_to_joint_origin_transform);
    const Eigen::Vector3d axis(j.axis.x, j.axis.y, j.axis.z);
    if (j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS)
      step = step * Eigen::AngleAxisd(q.at(j.name), axis.normalized());
    else if (j.type == urdf::Joint::PRISMATIC)
      step = step * Eigen::Translation3d(axis.normalized() * q.at(j.name) * 1e-3);
    T = step * T;
  }
  EXPECT_EQ(robot.getRoot()->name, "world");
  return T;
}

void round_trip(const std::string& robot_text, const std::string& options,
                const std::string& name) {
  SCOPED_TRACE(name);
  TempDir dir("urdf-round-trip-" + name);
  write_text(dir / "robot.urdf", robot_text);
  const auto imported = run_cli("model --urdf " + (dir / "robot.urdf") + options +
                                " --tip tool_mount --out " + (dir / "model.json"));
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const auto model = load_model(dir / "model.json");
  EXPECT_EQ(model->mechanism().actuator_names(),
            (std::vector<std::string>{"j1", "j2", "j3", "j4", "j5", "j6"}));
  EXPECT_EQ(model->mechanism().actuators()[3].unit, "mm");
  const auto json = nlohmann::json::parse(read_text(dir / "model.json"));
  EXPECT_DOUBLE_EQ(json["mechanism"]["joints"][3]["lower"].get<double>(), -50.0);
  EXPECT_DOUBLE_EQ(json["mechanism"]["joints"][3]["upper"].get<double>(), 100.0);
  EXPECT_FALSE(json["mechanism"]["joints"][4].contains("lower_deg"));  // continuous

  // The truth: the imported model with every parameter moved; data without noise.
  const auto simulated = run_cli(
      "simulate --model " + (dir / "model.json") +
      " --poses 60 --noise-half-width 0 --param-error 0.5mm,0.002rad --seed 4 --write-data " +
      (dir / "data.csv"));
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;

  // Default mask: the data choose; every fixed parameter is named with what it duplicates.
  const auto calibrated =
      run_cli("calibrate --model " + (dir / "model.json") + " --data " + (dir / "data.csv") +
              " --out " + (dir / "calibrated.json") + " --json " + (dir / "report.json"));
  ASSERT_EQ(calibrated.exit_code, 0) << calibrated.err;
  EXPECT_NE(calibrated.err.find("are fixed at their model values"), std::string::npos)
      << calibrated.err;
  // One row of the report's table of fixed parameters, and the JSON's sentence.
  const std::size_t row = calibrated.out.find("\n  tracker.frame.x ");
  ASSERT_NE(row, std::string::npos) << calibrated.out;
  const std::string line = calibrated.out.substr(row + 1, calibrated.out.find('\n', row + 1) - row);
  EXPECT_NE(line.find("tracker's frame, shift along x"), std::string::npos) << line;
  EXPECT_NE(line.find("moves the readings as"), std::string::npos) << line;
  const auto report = nlohmann::json::parse(read_text(dir / "report.json"));
  bool sentence = false;
  for (const auto& text : report["null_directions"])
    sentence = sentence || text.get<std::string>().rfind(
                               "tracker.frame.x (tracker's frame, shift along x) moves the "
                               "readings as",
                               0) == 0;
  EXPECT_TRUE(sentence) << report["null_directions"].dump();
  EXPECT_LT(report["final_cost"].get<double>(), 1e-12);
  ASSERT_TRUE(report.contains("null_directions"));
  EXPECT_EQ(report["null_directions"].size(), report["fixed_by_identifiability"].size());
  // An imported arm's forward kinematics is closed form: no home_pose "nearest assembly" warning.
  EXPECT_EQ(calibrated.err.find("home_pose"), std::string::npos) << calibrated.err;
  EXPECT_TRUE(report["warnings"].empty()) << report["warnings"];

  // observability says beforehand what calibrate keeps.
  const auto observed = run_cli("observability --model " + (dir / "model.json") + " --data " +
                                (dir / "data.csv") + " --json " + (dir / "obs.json"));
  ASSERT_EQ(observed.exit_code, 0) << observed.err;
  const auto obs = nlohmann::json::parse(read_text(dir / "obs.json"));
  const auto calibrated_json = nlohmann::json::parse(read_text(dir / "calibrated.json"));
  EXPECT_EQ(obs["calibrate_keeps"], calibrated_json["free"]);
  EXPECT_EQ(obs["null_directions"], report["null_directions"]);

  // An explicit mask is the user's: rank deficient, it stops and names null directions.
  const auto explicit_mask = run_cli("calibrate --model " + (dir / "model.json") + " --data " +
                                     (dir / "data.csv") + " --free '*'");
  EXPECT_EQ(explicit_mask.exit_code, 2);
  EXPECT_NE(explicit_mask.err.find("null directions: "), std::string::npos) << explicit_mask.err;
  EXPECT_NE(explicit_mask.err.find("moves the readings as"), std::string::npos);

  const auto exported = run_cli("export --model " + (dir / "calibrated.json") +
                                " --format urdf --out " + (dir / "out.urdf"));
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const std::string urdf_text = read_text(dir / "out.urdf");
  for (const char* kept :
       {"package://testbot/meshes/base.stl", "a comment the export keeps", "Gazebo/Grey",
        "<mass value=\"2.5\"", "effort=\"10\"", "<robot name=\"testbot\""})
    EXPECT_NE(urdf_text.find(kept), std::string::npos) << kept;
  if (std::system("command -v check_urdf >/dev/null 2>&1") == 0) {
    const int status = std::system(("check_urdf " + (dir / "out.urdf") + " >/dev/null").c_str());
    EXPECT_EQ(status, 0) << "check_urdf rejects the export";
  } else {
    ADD_FAILURE() << "check_urdf is not installed (apt-get install liburdfdom-tools)";
  }

  // world -> tcp of the exported URDF against the calibrated model, every configuration.
  const urdf::ModelInterfaceSharedPtr robot = urdf::parseURDF(urdf_text);
  ASSERT_TRUE(robot);
  const auto calibrated_model = load_model(dir / "calibrated.json");
  const MeasurementTable table = read_measurements(dir / "data.csv", *calibrated_model);
  const VectorXd values = calibrated_model->parameters().nominal_values();
  auto ws = calibrated_model->make_workspace();
  VectorXd predicted(calibrated_model->num_readings());
  double worst = 0;
  for (int c = 0; c < table.data.size(); ++c) {
    const VectorXd q = table.data.actuators.row(c).transpose();
    ASSERT_TRUE(calibrated_model->predict(values, q, predicted, nullptr, ws).ok());
    std::map<std::string, double> by_name;
    for (int i = 0; i < q.size(); ++i)
      by_name[calibrated_model->mechanism().actuator_names()[i]] = q[i];
    const Eigen::Isometry3d T = urdf_world_to_tcp(*robot, by_name);
    worst = std::max(worst, (T.translation() * 1e3 - predicted.head<3>()).norm());
    if (predicted.size() == 6)  // a pose tracker: the frame's orientation too (rad x 1 m)
      worst = std::max(worst, 1e3 * (log_so3(T.linear()) - predicted.tail<3>()).norm());
  }
  EXPECT_LT(worst, 1e-6) << "mm, over " << table.data.size() << " configurations";
  // And the calibration did move tcp: the nominal model's export is elsewhere.
  const auto nominal_export = run_cli("export --model " + (dir / "model.json") +
                                      " --format urdf --out " + (dir / "nominal.urdf"));
  ASSERT_EQ(nominal_export.exit_code, 0) << nominal_export.err;
  EXPECT_NE(read_text(dir / "nominal.urdf"), urdf_text);
}

TEST(Urdf, ImportCalibrateExportRoundTrip) {
  // The arm's base below the URDF's root: the export adds `world` above the root.
  round_trip(kRobot, " --base base_link --point 10,20,30", "base-below-root");
  // A URDF whose root is already `world` (the chain starting there): it stays the root and
  // becomes the measurement frame; the joints from it carry the calibrated base.
  std::string rooted = kRobot;
  for (std::size_t at; (at = rooted.find("\"stand\"")) != std::string::npos;)
    rooted.replace(at, 7, "\"world\"");
  round_trip(rooted, " --point 10,20,30", "root-is-world");
  // A pose tracker: tcp is the marker's frame, orientation included.
  round_trip(kRobot, " --base base_link --sensor pose-tracker", "pose-tracker");
}

// The preset ur5-urdf carries the example's URDF text, and its geometry is that text's: the
// export (which re-reads the text with urdfdom and compares) accepts it.
TEST(Urdf, PresetHoldsTheExampleUrdfAndExportsIntoIt) {
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "KINCAL_SOURCE_DIR is set by ctest";
  EXPECT_EQ(read_text(std::string(source) + "/examples/ur5-laser-tracker/ur5.urdf"),
            ur5_urdf_text());
  TempDir dir("urdf-preset");
  ASSERT_EQ(run_cli("model --preset ur5-urdf --out " + (dir / "m.json")).exit_code, 0);
  const auto exported =
      run_cli("export --model " + (dir / "m.json") + " --format urdf --out " + (dir / "m.urdf"));
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_NE(read_text(dir / "m.urdf").find("<link name=\"tcp\""), std::string::npos);
  const auto json =
      run_cli("export --model " + (dir / "m.json") + " --format json --out " + (dir / "m.j"));
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(nlohmann::json::parse(read_text(dir / "m.j"))["joints"].size(), 6u);
  const auto csv =
      run_cli("export --model " + (dir / "m.json") + " --format csv --out " + (dir / "m.csv"));
  EXPECT_EQ(csv.exit_code, 2);
  EXPECT_NE(csv.err.find("no DH table"), std::string::npos) << csv.err;
  // A model whose joints were edited after import no longer matches its URDF: refused.
  auto edited = nlohmann::json::parse(read_text(dir / "m.json"));
  edited["mechanism"]["joints"][2]["origin"]["position"][0] = -430.0;
  std::ofstream(dir / "edited.json") << edited.dump(2);
  const auto refused = run_cli("export --model " + (dir / "edited.json") + " --format urdf --out " +
                               (dir / "e.urdf"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("differs from its URDF text (joint 'elbow_joint')"), std::string::npos)
      << refused.err;
}

// The example's UR5 URDF, imported, is Universal Robots' DH table: its flange is where the
// DH preset `ur5` (models/serial_arm_presets.cpp, another code path) puts the end, at any
// joint values.
TEST(Urdf, TheExampleUr5IsUniversalRobotsDhTable) {
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  ASSERT_NE(source, nullptr);
  TempDir dir("urdf-ur5-dh");
  const auto imported =
      run_cli("model --urdf " + std::string(source) +
              "/examples/ur5-laser-tracker/ur5.urdf --tip flange --out " + (dir / "ur5.json"));
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const auto urdf = load_model(dir / "ur5.json");
  const auto dh = ModelRegistry::global().make_preset("ur5");
  const VectorXd pu = urdf->parameters().nominal_values().head(urdf->mechanism().num_parameters());
  const VectorXd pd = dh->parameters().nominal_values().head(dh->mechanism().num_parameters());
  for (int trial = 0; trial < 10; ++trial) {
    VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = 2.5 * std::sin(1.3 * trial + 0.7 * i + 0.2);
    const Pose a = urdf->mechanism().forward_kinematics(pu, q, Pose{}).pose;
    const Pose b = dh->mechanism().forward_kinematics(pd, q, Pose{}).pose;
    EXPECT_LT((a.translation - b.translation).norm(), 1e-9) << "trial " << trial;
    EXPECT_LT((a.rotation - b.rotation).norm(), 1e-12) << "trial " << trial;
  }
}

// An arm calibrated from sockets alone (docs/fixtures.md) exports too: world is the arm's base
// frame, in which the sockets' centres were estimated, and tcp the tool point that went into
// them, so world -> tcp of the URDF, read back by urdfdom, is a socket's reading plus its
// centre. A model with a tracker and sockets has no one measured point: refused.
TEST(Urdf, ASocketModelExportsTheToolPointInTheSocketsFrame) {
  TempDir dir("urdf-sockets");
  write_text(dir / "robot.urdf", kRobot);
  ASSERT_EQ(run_cli("model --urdf " + (dir / "robot.urdf") +
                    " --base base_link --tip tool_mount --out " + (dir / "tracked.json"))
                .exit_code,
            0);
  auto json = nlohmann::json::parse(read_text(dir / "tracked.json"));
  const auto tracker = json["sensors"][0];
  json["sensors"] = nlohmann::json::array(
      {{{"type", "socket"}, {"name", "s0"}, {"point", {400.0, -20.0, 250.0}}},
       {{"type", "socket"}, {"name", "s1"}, {"point", {430.0, 20.0, 250.0}}}});
  json["free"] = {"s*"};
  write_text(dir / "sockets.json", json.dump(2));
  const auto model = load_model(dir / "sockets.json");
  // Every parameter moved, as a calibration would move them (base and tool included).
  VectorXd values = model->parameters().nominal_values();
  for (int i = 0; i < values.size(); ++i)
    values[i] += (model->parameters()[i].unit == "rad" ? 0.01 : 3.0) * std::sin(1.7 * i + 0.3);
  write_text(dir / "moved.json", model_to_json(*model, values).dump(2));
  const auto exported = run_cli("export --model " + (dir / "moved.json") + " --format urdf --out " +
                                (dir / "s.urdf"));
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const std::string urdf_text = read_text(dir / "s.urdf");
  EXPECT_NE(urdf_text.find("centres of the sockets were estimated"), std::string::npos);
  if (std::system("command -v check_urdf >/dev/null 2>&1") == 0) {
    EXPECT_EQ(std::system(("check_urdf " + (dir / "s.urdf") + " >/dev/null").c_str()), 0);
  } else {
    ADD_FAILURE() << "check_urdf is not installed (apt-get install liburdfdom-tools)";
  }
  const urdf::ModelInterfaceSharedPtr robot = urdf::parseURDF(urdf_text);
  ASSERT_TRUE(robot);
  const auto moved = load_model(dir / "moved.json");
  const VectorXd saved = moved->parameters().nominal_values();
  const int centre = moved->parameters().index_of("s0.point.x");
  auto ws = moved->make_workspace();
  VectorXd readings(moved->num_readings());
  for (int trial = 0; trial < 8; ++trial) {
    VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = 1.2 * std::sin(0.9 * trial + 2.1 * i);
    q[3] = 40 * std::sin(0.7 * trial);  // the prismatic joint, mm within its limits
    ASSERT_TRUE(moved->predict(saved, q, readings, nullptr, ws).ok());
    std::map<std::string, double> by_name;
    for (int i = 0; i < 6; ++i) by_name[moved->mechanism().actuator_names()[i]] = q[i];
    const Eigen::Isometry3d T = urdf_world_to_tcp(*robot, by_name);
    EXPECT_LT((T.translation() * 1e3 - (readings.head<3>() + saved.segment<3>(centre))).norm(),
              1e-9)
        << "trial " << trial;
  }
  // The tool point moved with the parameters: the nominal model's export puts tcp elsewhere.
  ASSERT_EQ(run_cli("export --model " + (dir / "sockets.json") + " --format urdf --out " +
                    (dir / "nominal.urdf"))
                .exit_code,
            0);
  EXPECT_NE(read_text(dir / "nominal.urdf"), urdf_text);

  json["sensors"].push_back(tracker);
  write_text(dir / "mixed.json", json.dump(2));
  const auto mixed = run_cli("export --model " + (dir / "mixed.json") + " --format urdf --out " +
                             (dir / "m.urdf"));
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_NE(mixed.err.find("a tracker and sockets"), std::string::npos) << mixed.err;
  EXPECT_FALSE(std::ifstream(dir / "m.urdf").good());
}

TEST(Urdf, BadImportsAreOneLineAndExitTwo) {
  TempDir dir("urdf-bad");
  write_text(dir / "robot.urdf", kRobot);
  write_text(dir / "broken.urdf", "<robot name=\"x\"><link name=\"a\"/><joint/></robot>");
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"--urdf " + (dir / "robot.urdf") + " --tip nowhere", "no link 'nowhere'"},
      {"--urdf " + (dir / "robot.urdf"), "--tip"},
      {"--urdf " + (dir / "robot.urdf") + " --tip l1 --base tool_mount", "is not below link"},
      {"--urdf " + (dir / "robot.urdf") + " --tip l1 --sensor camera", "--sensor 'camera'"},
      {"--urdf " + (dir / "broken.urdf") + " --tip a", "not a valid URDF"},
      {"--urdf " + (dir / "missing.urdf") + " --tip a", "missing.urdf"},
      {"--preset ur5 --tip l1", "--tip needs --urdf"},
  };
  for (const Case& c : cases) {
    const auto result = run_cli("model " + c.args + " --out " + (dir / "m.json"));
    EXPECT_EQ(result.exit_code, 2) << c.args;
    EXPECT_NE(result.err.find(c.expected), std::string::npos) << c.args << ": " << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));
  }
}

}  // namespace
}  // namespace kincal
