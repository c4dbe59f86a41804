// The hexapod in model files and its presets.
//   "mechanism": { "type": "hexapod-6ups",
//                  "home_pose": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//                  "legs": [ { "name": "leg1", "base": [x, y, z], "platform": [x, y, z],
//                              "offset": 0 }, ... six ] }

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {

namespace {

using namespace json_field;

std::shared_ptr<const Mechanism> read_hexapod(const Json& j, const JsonPath& where) {
  check_keys(j, where, {"type", "home_pose", "legs"});
  HexapodGeometry g;
  g.home = pose(member(j, "home_pose", where), where / "home_pose");
  const Json& legs = member(j, "legs", where);
  if (!legs.is_array() || legs.size() != Hexapod::kLegs)
    (where / "legs").fail("expected an array of 6 leg objects");
  for (int leg = 0; leg < Hexapod::kLegs; ++leg) {
    const JsonPath at = (where / "legs")[leg];
    const Json& l = legs[leg];
    if (!l.is_object()) at.fail("expected an object with base, platform, offset");
    check_keys(l, at, {"name", "base", "platform", "offset"});
    const std::string expected_name = "leg" + std::to_string(leg + 1);
    if (l.contains("name") && l["name"] != expected_name)
      (at / "name").fail("expected \"" + expected_name + "\" (legs are listed in order)");
    g.base_joints[leg] = vector3(member(l, "base", at), at / "base");
    g.platform_joints[leg] = vector3(member(l, "platform", at), at / "platform");
    g.leg_offsets[leg] = number_or(l, "offset", 0.0, at);
  }
  return std::make_shared<Hexapod>(g);
}

Json write_hexapod(const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values) {
  const auto& hexapod = dynamic_cast<const Hexapod&>(mechanism);
  Json out;
  out["home_pose"] = pose_json(hexapod.home_pose());
  out["legs"] = Json::array();
  for (int leg = 0; leg < Hexapod::kLegs; ++leg)
    out["legs"].push_back({{"name", hexapod.actuators()[leg].name},
                           {"base", array3(values.segment<3>(Hexapod::base_index(leg)))},
                           {"platform", array3(values.segment<3>(Hexapod::platform_index(leg)))},
                           {"offset", values[Hexapod::offset_index(leg)]}});
  return out;
}

}  // namespace

void register_hexapod(ModelRegistry& registry) {
  registry.add_mechanism({"hexapod-6ups",
                          "6-UPS parallel hexapod: six legs between base and platform joints, "
                          "actuators are leg lengths (mm)",
                          read_hexapod, write_hexapod});
  registry.add_preset({"cube-hexapod",
                       "the cube hexapod of Choi & Lim, 'Calibration of geometric errors of a "
                       "parallel manipulator using a sensor of length measurement' (Table 1), "
                       "one length gauge; the paper's 24 free joint coordinates",
                       make_cube_hexapod});
  registry.add_preset({"stewart-6-6",
                       "a general 6-6 Gough-Stewart platform, nominal geometry of Nategh & "
                       "Agheli, 'A total solution to kinematic calibration of hexapod machine "
                       "tools with a minimum number of measurement configurations and superior "
                       "accuracies' (2009, Table 1), one length gauge",
                       make_stewart_6_6});
}

}  // namespace kincal
