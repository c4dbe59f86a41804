// The plug-in: the five-bar linkage and the laser displacement sensor in model files, a
// preset, an export format, and the one line that makes this library a kincal plug-in.
//   "mechanism": { "type": "five-bar", "home": [x, y],
//                  "arms": [ { "name": "arm1", "base": [x, y], "proximal": l,
//                              "distal": d, "offset_deg": o, "elbow": 1 }, ... two ] }
//   { "type": "laser-displacement", "name": "laser_x", "origin": [x, y, z],
//     "azimuth_deg": a, "elevation_deg": e,
//     "plane": { "azimuth_deg": a, "elevation_deg": e, "distance": h } }

#include <cmath>
#include <kincal/framework/extension/plugin.hpp>
#include <kincal/framework/io/json_input.hpp>

#include "five_bar.hpp"
#include "laser_displacement.hpp"

namespace five_bar_plugin {

using namespace kincal;
using namespace kincal::json_field;

namespace {

constexpr double kDegree = M_PI / 180;

Eigen::Vector2d vector2(const Json& value, const JsonPath& where) {
  if (!value.is_array() || value.size() != 2)
    where.fail("expected [x, y] (the five-bar moves in the plane z = 0), got " +
               json_excerpt(value));
  return Eigen::Vector2d(number(value[0], where[0]), number(value[1], where[1]));
}

std::shared_ptr<const Mechanism> read_five_bar(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "home", "arms"});
  FiveBarGeometry g;
  g.home = vector2(member(j, "home", where), where / "home");
  const Json& arms = member(j, "arms", where);
  if (!arms.is_array() || arms.size() != 2) (where / "arms").fail("expected two arm objects");
  for (int i = 0; i < 2; ++i) {
    const JsonPath at = (where / "arms")[i];
    const Json& a = object(arms[i], at);
    check_keys(a, at, {"name", "base", "proximal", "distal", "offset_deg", "elbow"});
    FiveBarArm& arm = g.arms[i];
    arm.base = vector2(member(a, "base", at), at / "base");
    arm.proximal = number(member(a, "proximal", at), at / "proximal");
    arm.distal = number(member(a, "distal", at), at / "distal");
    arm.offset = number_or(a, "offset_deg", 0, at) * kDegree;
    const double elbow = number_or(a, "elbow", 1, at);
    if (elbow != 1 && elbow != -1) (at / "elbow").fail("expected 1 (left) or -1 (right)");
    arm.elbow = static_cast<int>(elbow);
    if (!(arm.proximal > 0) || !(arm.distal > 0)) at.fail("link lengths must be > 0");
  }
  return std::make_shared<FiveBar>(g);
}

Json write_five_bar(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& v) {
  const auto& five_bar = dynamic_cast<const FiveBar&>(mechanism);
  const FiveBarGeometry& g = five_bar.nominal_geometry();
  Json out = {{"home", {g.home.x(), g.home.y()}}, {"arms", Json::array()}};
  for (int i = 0; i < 2; ++i)
    out["arms"].push_back({{"name", "arm" + std::to_string(i + 1)},
                           {"base", {v[FiveBar::base_index(i)], v[FiveBar::base_index(i) + 1]}},
                           {"proximal", v[FiveBar::proximal_index(i)]},
                           {"distal", v[FiveBar::distal_index(i)]},
                           {"offset_deg", v[FiveBar::offset_index(i)] / kDegree},
                           {"elbow", g.arms[i].elbow}});
  return out;
}

std::shared_ptr<const Sensor> read_laser(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "name", "origin", "azimuth_deg", "elevation_deg", "plane"});
  LaserGeometry g;
  g.origin = vector3(member(j, "origin", where), where / "origin");
  g.azimuth = number_or(j, "azimuth_deg", 0, where) * kDegree;
  g.elevation = number_or(j, "elevation_deg", 0, where) * kDegree;
  const JsonPath at = where / "plane";
  const Json& plane = object(member(j, "plane", where), at);
  check_keys(plane, at, {"azimuth_deg", "elevation_deg", "distance"});
  g.plane_azimuth = number_or(plane, "azimuth_deg", 0, at) * kDegree;
  g.plane_elevation = number_or(plane, "elevation_deg", 0, at) * kDegree;
  g.plane_distance = number_or(plane, "distance", 0, at);
  return std::make_shared<LaserDisplacement>(name(member(j, "name", where), where / "name"), g);
}

Json write_laser(const Sensor& sensor, const Eigen::Ref<const VectorXd>& v) {
  using L = LaserDisplacement;
  return {{"name", sensor.name()},
          {"origin", array3(v.segment<3>(L::kOriginX))},
          {"azimuth_deg", v[L::kAzimuth] / kDegree},
          {"elevation_deg", v[L::kElevation] / kDegree},
          {"plane",
           {{"azimuth_deg", v[L::kPlaneAzimuth] / kDegree},
            {"elevation_deg", v[L::kPlaneElevation] / kDegree},
            {"distance", v[L::kPlaneDistance]}}}};
}

// A 200 mm wide five-bar (proximal links 150 mm, distal 200 mm, working mode "+-": elbows
// outside), its end effector at (0, 250) mm at home, watched by two laser displacement
// sensors: one along +x to a plane facing it 20 mm left of the end effector, one along -y to
// a plane 20 mm above it. The lasers measure the end effector's x and y; arm1's base fixes
// the base frame, and the planes' distances are calibrated with the linkage: 10 free
// parameters.
std::shared_ptr<MeasurementModel> make_demo() {
  FiveBarGeometry g;
  g.arms[0] = {Eigen::Vector2d(-100, 0), 150, 200, 0, 1};
  g.arms[1] = {Eigen::Vector2d(100, 0), 150, 200, 0, -1};
  g.home = Eigen::Vector2d(0, 250);
  LaserGeometry x;
  x.origin = Vector3d(-400, 250, 0);
  x.plane_azimuth = M_PI;  // the plane faces the laser: normal -x
  x.plane_distance = 20;
  LaserGeometry y;
  y.origin = Vector3d(0, 600, 0);
  y.azimuth = -M_PI / 2;  // the beam points down, -y
  y.plane_azimuth = M_PI / 2;
  y.plane_distance = 20;
  auto model = std::make_shared<MeasurementModel>(
      std::make_shared<FiveBar>(g), std::vector<std::shared_ptr<const Sensor>>{
                                        std::make_shared<LaserDisplacement>("laser_x", x),
                                        std::make_shared<LaserDisplacement>("laser_y", y)});
  model->parameters().set_free("arm*", true);
  model->parameters().set_free("arm1.base.*", false);
  model->parameters().set_free("laser_?.plane.distance", true);
  return model;
}

// A further export format: the linkage as a table for a controller, one row per arm.
std::string export_arm_table(const MeasurementModel& model, const ExportOrigin& origin) {
  const VectorXd v = model.parameters().nominal_values();
  std::string out = "# five-bar arms from " + origin.model_file + " (sha256 " + origin.sha256 +
                    ")\narm,base_x_mm,base_y_mm,proximal_mm,distal_mm,offset_deg,elbow\n";
  const auto& five_bar = dynamic_cast<const FiveBar&>(model.mechanism());
  char row[256];
  for (int i = 0; i < 2; ++i) {
    std::snprintf(row, sizeof row, "arm%d,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", i + 1,
                  v[FiveBar::base_index(i)], v[FiveBar::base_index(i) + 1],
                  v[FiveBar::proximal_index(i)], v[FiveBar::distal_index(i)],
                  v[FiveBar::offset_index(i)] / kDegree, five_bar.nominal_geometry().arms[i].elbow);
    out += row;
  }
  return out;
}

}  // namespace

void register_five_bar_plugin(ModelRegistry& models, SolverRegistry&) {
  models.add_mechanism({"five-bar",
                        "planar five-bar linkage (5R): two actuated base joints, the end "
                        "effector where the distal links meet (plug-in example)",
                        read_five_bar, write_five_bar});
  models.add_sensor({"laser-displacement",
                     "distance along a laser beam from the base to a plane on the platform "
                     "(plug-in example)",
                     read_laser, write_laser});
  models.add_preset({"five-bar-demo",
                     "a 200 mm wide five-bar with two laser displacement sensors "
                     "(examples/plugin, docs/extending.md)",
                     make_demo});
  models.add_export_format({"arm-table", "five-bar",
                            "one CSV row per arm: base, link lengths, offset, elbow",
                            export_arm_table});
}

}  // namespace five_bar_plugin

KINCAL_PLUGIN(five_bar_plugin::register_five_bar_plugin)
