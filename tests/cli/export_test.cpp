// kincal export: the URDF of a preset arm read back by an independent reader gives kincal's
// forward kinematics; the CSV and JSON tables hold the model's values; a format the
// mechanism cannot take is one error line.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "cli_runner.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/models/export_formats.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;

std::vector<double> numbers_in(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> out;
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

// One URDF joint as a robot-description reader sees it (metres, radians).
struct UrdfJoint {
  std::string type;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
};

// The joints of a chain in document order (the export writes them base to tool), read from
// the <joint> elements alone: type, origin xyz/rpy (R = Rz(y) Ry(p) Rx(r), URDF's fixed-axis
// roll-pitch-yaw) and axis.
std::vector<UrdfJoint> read_urdf_chain(const std::string& urdf) {
  std::vector<UrdfJoint> joints;
  const std::regex joint(R"re(<joint name="[^"]*" type="([a-z]+)">([\s\S]*?)</joint>)re");
  const std::regex origin(R"re(<origin xyz="([^"]*)" rpy="([^"]*)"/>)re");
  const std::regex axis(R"re(<axis xyz="([^"]*)"/>)re");
  for (std::sregex_iterator it(urdf.begin(), urdf.end(), joint), end; it != end; ++it) {
    UrdfJoint j;
    j.type = (*it)[1];
    const std::string body = (*it)[2];
    std::smatch m;
    if (std::regex_search(body, m, origin)) {
      const auto xyz = numbers_in(m[1]), rpy = numbers_in(m[2]);
      EXPECT_EQ(xyz.size(), 3u);
      EXPECT_EQ(rpy.size(), 3u);
      j.origin.translation() = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      j.origin.linear() = (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
                              .toRotationMatrix();
    }
    if (std::regex_search(body, m, axis)) {
      const auto a = numbers_in(m[1]);
      j.axis = Eigen::Vector3d(a[0], a[1], a[2]);
    }
    joints.push_back(j);
  }
  return joints;
}

Eigen::Isometry3d urdf_fk(const std::vector<UrdfJoint>& chain, const VectorXd& q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  int next = 0;
  for (const UrdfJoint& j : chain) {
    T = T * j.origin;
    if (j.type == "revolute")
      T = T * Eigen::AngleAxisd(q[next++], j.axis);
    else if (j.type == "prismatic")
      T = T * Eigen::Translation3d(j.axis * q[next++] * 1e-3);  // q in mm
  }
  return T;
}

void set_value(MeasurementModel& model, int i, double v) {
  model.parameters().for_each_matching(model.parameters()[i].name,
                                       [v](Parameter& p) { p.nominal = v; });
}

// A calibrated-looking arm: every parameter of the preset moved, so that no term is zero by
// accident (Hayati links, base and tool rotations included).
MeasurementModel perturbed(const std::string& preset, VectorXd& values) {
  auto model = make_preset(preset);
  values = model->parameters().nominal_values();
  for (int i = 0; i < values.size(); ++i)
    values[i] += (model->parameters()[i].unit == "rad" ? 0.01 : 3.0) * std::sin(1.7 * i + 0.3);
  for (int i = 0; i < values.size(); ++i) set_value(*model, i, values[i]);
  return *model;
}

// world -> tcp of the exported URDF is what the tracker would read: the tracker's frame,
// the base and tool frames and the target or marker are all in it (an export that dropped
// them would move tcp).
TEST(Export, UrdfOfEachPresetArmGivesTheTrackersReadings) {
  for (const std::string preset : {"puma560", "ur5"}) {
    VectorXd values;
    const MeasurementModel model = perturbed(preset, values);
    const std::string urdf = export_urdf(model, {"calibrated.json", "abc"});
    const auto chain = read_urdf_chain(urdf);
    const auto& arm = dynamic_cast<const SerialArm&>(model.mechanism());
    // world -> base_link, the joints, tool, tool0 -> tcp.
    ASSERT_EQ(chain.size(), static_cast<std::size_t>(arm.num_joints() + 3)) << preset;
    EXPECT_EQ(chain.front().type, "fixed");
    EXPECT_EQ(chain.back().type, "fixed");
    auto ws = model.make_workspace();
    VectorXd readings(model.num_readings());
    for (int trial = 0; trial < 5; ++trial) {
      VectorXd q(arm.num_joints());
      for (int i = 0; i < q.size(); ++i) q[i] = std::sin(0.9 * trial + 2.1 * i) * 1.2;
      ASSERT_TRUE(model.predict(values, q, readings, nullptr, ws).ok());
      const Eigen::Isometry3d T = urdf_fk(chain, q);
      EXPECT_LT((T.translation() * 1e3 - readings.head<3>()).norm(), 1e-9)
          << preset << " trial " << trial;
      if (model.num_readings() == 6) {  // a pose tracker also reads the orientation
        EXPECT_LT((log_so3(T.linear()) - readings.tail<3>()).norm(), 1e-9)
            << preset << " trial " << trial;
      }
    }
    // Limits: home +- the actuator's range.
    EXPECT_NE(urdf.find("<limit lower=\""), std::string::npos);
  }
}

// A DH arm calibrated from sockets (no tracker): world is the arm's base frame, where the
// sockets' centres are, and tcp the tool point, so world -> tcp is a reading plus its centre.
TEST(Export, UrdfOfADhArmWithSocketsGivesTheToolPoint) {
  VectorXd values;
  const MeasurementModel tracked = perturbed("puma560", values);
  auto j = model_to_json(tracked, values);
  j["sensors"] = nlohmann::ordered_json::array(
      {{{"type", "socket"}, {"name", "s0"}, {"point", {500.0, 100.0, 200.0}}}});
  j["free"] = {"s*"};
  const auto model = model_from_json(j, "sockets.json");
  const VectorXd nominal = model->parameters().nominal_values();
  const std::string urdf = export_urdf(*model, {"sockets.json", "abc"});
  EXPECT_NE(urdf.find("centres of the sockets were estimated"), std::string::npos);
  const auto chain = read_urdf_chain(urdf);
  const auto& arm = dynamic_cast<const SerialArm&>(model->mechanism());
  ASSERT_EQ(chain.size(), static_cast<std::size_t>(arm.num_joints() + 3));  // world, tcp
  const int centre = model->parameters().index_of("s0.point.x");
  auto ws = model->make_workspace();
  VectorXd readings(model->num_readings());
  for (int trial = 0; trial < 5; ++trial) {
    VectorXd q(arm.num_joints());
    for (int i = 0; i < q.size(); ++i) q[i] = std::sin(0.9 * trial + 2.1 * i) * 1.2;
    ASSERT_TRUE(model->predict(nominal, q, readings, nullptr, ws).ok());
    EXPECT_LT(
        (urdf_fk(chain, q).translation() * 1e3 - (readings + nominal.segment<3>(centre))).norm(),
        1e-9)
        << "trial " << trial;
  }
}

// The CSV row of each leg holds the model's own values, full precision.
TEST(Export, ParallelCsvHoldsTheModelsJointCoordinatesAndOffsets) {
  for (const std::string preset : {"cube-hexapod", "planar-3rpr"}) {
    VectorXd values;
    auto model = make_preset(preset);
    values = model->parameters().nominal_values();
    for (int i = 0; i < values.size(); ++i) set_value(*model, i, values[i] + 0.1 * i);
    values = model->parameters().nominal_values();
    const std::string csv = export_csv(*model, {"c.json", "abc"});
    EXPECT_NE(csv.find("# leg length = actuator value + offset"), std::string::npos) << csv;
    std::istringstream in(csv);
    std::string line;
    std::vector<std::string> header;
    int legs = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::vector<std::string> fields;
      std::stringstream ss(line);
      for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
      if (header.empty()) {
        header = fields;
        continue;
      }
      ASSERT_EQ(fields.size(), header.size());
      const std::string leg = fields[0];
      ++legs;
      auto value_of = [&](const std::string& name, double fallback) {
        for (int i = 0; i < model->num_parameters(); ++i)
          if (model->parameters()[i].name == name) return values[i];
        return fallback;
      };
      const char* columns[] = {"base_x",     "base_y",     "base_z", "platform_x",
                               "platform_y", "platform_z", "offset"};
      const char* names[] = {".base.x",     ".base.y",     ".base.z", ".platform.x",
                             ".platform.y", ".platform.z", ".offset"};
      for (int c = 0; c < 7; ++c) {
        ASSERT_EQ(header[c + 1], columns[c]);
        EXPECT_EQ(std::stod(fields[c + 1]), value_of(leg + names[c], 0.0)) << preset << " " << leg;
      }
      // home_length is the leg's length at home_pose.
      EXPECT_NEAR(std::stod(fields[9]), std::stod(fields[8]) + std::stod(fields[7]), 1e-9);
    }
    EXPECT_EQ(legs, static_cast<int>(model->mechanism().actuators().size())) << preset;
  }
}

TEST(Export, CliWritesEachFormatAndRefusesUrdfForAHexapod) {
  TempDir dir("export");
  const std::string hex = dir / "hex.json", arm = dir / "arm.json";
  ASSERT_EQ(run_cli("model --out " + hex).exit_code, 0);
  ASSERT_EQ(run_cli("model --preset ur5 --out " + arm).exit_code, 0);
  const auto urdf = run_cli("export --model " + arm + " --format urdf --out " + (dir / "a.urdf"));
  EXPECT_EQ(urdf.exit_code, 0) << urdf.err;
  EXPECT_NE(read_text(dir / "a.urdf").find("<robot name="), std::string::npos);
  const auto json = run_cli("export --model " + hex + " --format json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["format"], "kincal-export");
  EXPECT_EQ(j["legs"].size(), 6u);
  const auto model = load_model(hex);
  EXPECT_EQ(j["legs"][2]["platform"][1].get<double>(),
            model->parameters().nominal_values()[model->parameters().index_of("leg3.platform.y")]);
  const auto refused =
      run_cli("export --model " + hex + " --format urdf --out " + (dir / "h.urdf"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_NE(refused.err.find("not a serial arm"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "h.urdf"));
  EXPECT_EQ(run_cli("export --model " + hex + " --format step").exit_code, 2);
}

}  // namespace
}  // namespace kincal
