#include "kincal/models/model_io.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "kincal/framework/json_input.hpp"
#include "kincal/framework/message_excerpt.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& source, const std::string& where,
                       const std::string& what) {
  throw std::invalid_argument(source + ": " + (where.empty() ? "" : where + ": ") + what);
}

// Typos such as "fre" or "ofset" must not pass silently.
void check_keys(const Json& object, const std::string& source, const std::string& where,
                const std::set<std::string>& allowed) {
  for (const auto& item : object.items()) {
    if (allowed.count(item.key())) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(source, where,
         "unknown key '" + message_excerpt(item.key()) + "' (expected " + list + ")");
  }
}

const Json& member(const Json& object, const std::string& key, const std::string& source,
                   const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) fail(source, where, "missing key '" + key + "'");
  return *it;
}

const Json& object_at(const Json& object, const std::string& key, const std::string& source,
                      const std::string& where) {
  const Json& value = member(object, key, source, where);
  const std::string path = where.empty() ? key : where + "." + key;
  if (!value.is_object()) fail(source, path, "expected an object");
  return value;
}

double number(const Json& value, const std::string& source, const std::string& where) {
  if (!value.is_number()) fail(source, where, "expected a number, got " + json_excerpt(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) fail(source, where, "expected a finite number");
  return v;
}

Vector3d vector3(const Json& value, const std::string& source, const std::string& where) {
  if (!value.is_array() || value.size() != 3)
    fail(source, where, "expected an array of 3 numbers [x, y, z], got " + json_excerpt(value));
  Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = number(value[a], source, where + "[" + std::to_string(a) + "]");
  return v;
}

// "+ 0.0" turns -0 into 0 so that files do not show "-0.0".
Json array3(const Vector3d& v) { return Json::array({v[0] + 0.0, v[1] + 0.0, v[2] + 0.0}); }

Json pose_to_json(const Pose& pose) {
  const Vector3d zyx = euler_zyx(pose.rotation);  // (alpha, beta, gamma) = (rz, ry, rx)
  const Vector3d xyz_deg(zyx[2] * 180 / kPi, zyx[1] * 180 / kPi, zyx[0] * 180 / kPi);
  return {{"position", array3(pose.translation)}, {"rotation_zyx_deg", array3(xyz_deg)}};
}

Pose pose_from_json(const Json& j, const std::string& source, const std::string& where) {
  check_keys(j, source, where, {"position", "rotation_zyx_deg"});
  Pose pose;
  pose.translation = vector3(member(j, "position", source, where), source, where + ".position");
  const Vector3d deg =
      vector3(member(j, "rotation_zyx_deg", source, where), source, where + ".rotation_zyx_deg");
  pose.rotation =
      rotation_from_euler_zyx(Vector3d(deg[2] * kPi / 180, deg[1] * kPi / 180, deg[0] * kPi / 180));
  return pose;
}

std::shared_ptr<Hexapod> hexapod_from_json(const Json& j, const std::string& source) {
  const std::string where = "mechanism";
  check_keys(j, source, where, {"type", "home_pose", "legs"});
  HexapodGeometry g;
  g.home = pose_from_json(object_at(j, "home_pose", source, where), source, where + ".home_pose");
  const Json& legs = member(j, "legs", source, where);
  if (!legs.is_array() || legs.size() != Hexapod::kLegs)
    fail(source, where + ".legs", "expected an array of 6 leg objects");
  for (int leg = 0; leg < Hexapod::kLegs; ++leg) {
    const std::string at = where + ".legs[" + std::to_string(leg) + "]";
    const Json& l = legs[leg];
    if (!l.is_object()) fail(source, at, "expected an object with base, platform, offset");
    check_keys(l, source, at, {"name", "base", "platform", "offset"});
    const std::string expected_name = "leg" + std::to_string(leg + 1);
    if (l.contains("name") && l["name"] != expected_name)
      fail(source, at + ".name", "expected \"" + expected_name + "\" (legs are listed in order)");
    g.base_joints[leg] = vector3(member(l, "base", source, at), source, at + ".base");
    g.platform_joints[leg] = vector3(member(l, "platform", source, at), source, at + ".platform");
    g.leg_offsets[leg] = l.contains("offset") ? number(l["offset"], source, at + ".offset") : 0.0;
  }
  return std::make_shared<Hexapod>(g);
}

std::shared_ptr<LengthGauge> gauge_from_json(const Json& j, const std::string& source,
                                             const std::string& at) {
  check_keys(j, source, at, {"type", "name", "base", "platform", "offset"});
  const Json& name = member(j, "name", source, at);
  // A CSV column, and the prefix of parameter names that "free" matches with globs.
  if (!name.is_string() || name.get<std::string>().empty() ||
      name.get<std::string>().find_first_of(", \t#\"*?") != std::string::npos)
    fail(source, at + ".name",
         "expected a non-empty name without commas, spaces, '#', quotes, '*' or '?' (it is a "
         "CSV column and part of parameter names)");
  const double offset = j.contains("offset") ? number(j["offset"], source, at + ".offset") : 0.0;
  return std::make_shared<LengthGauge>(
      name.get<std::string>(), vector3(member(j, "base", source, at), source, at + ".base"),
      vector3(member(j, "platform", source, at), source, at + ".platform"), offset);
}

std::string type_of(const Json& j, const std::string& source, const std::string& at) {
  const Json& type = member(j, "type", source, at);
  if (!type.is_string()) fail(source, at + ".type", "expected a string");
  return type.get<std::string>();
}

}  // namespace

Json model_to_json(const MeasurementModel& model, const VectorXd& values) {
  if (values.size() != model.num_parameters())
    throw std::invalid_argument("model_to_json: " + std::to_string(values.size()) +
                                " values for a model with " +
                                std::to_string(model.num_parameters()) + " parameters");
  const auto* hexapod = dynamic_cast<const Hexapod*>(&model.mechanism());
  if (!hexapod)
    throw std::invalid_argument("cannot write mechanism type '" + model.mechanism().type() +
                                "' to a model file");
  Json out;
  out["format"] = kModelFormat;
  out["version"] = kModelFormatVersion;
  out["units"] = "mm";
  Json mechanism;
  mechanism["type"] = hexapod->type();
  mechanism["home_pose"] = pose_to_json(hexapod->home_pose());
  mechanism["legs"] = Json::array();
  for (int leg = 0; leg < Hexapod::kLegs; ++leg)
    mechanism["legs"].push_back(
        {{"name", hexapod->actuator_names()[leg]},
         {"base", array3(values.segment<3>(Hexapod::base_index(leg)))},
         {"platform", array3(values.segment<3>(Hexapod::platform_index(leg)))},
         {"offset", values[Hexapod::offset_index(leg)]}});
  out["mechanism"] = mechanism;
  out["sensors"] = Json::array();
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const auto* gauge = dynamic_cast<const LengthGauge*>(model.sensors()[s].get());
    if (!gauge)
      throw std::invalid_argument("cannot write sensor type '" + model.sensors()[s]->type() +
                                  "' to a model file");
    const int o = model.sensor_parameter_offset(static_cast<int>(s));
    out["sensors"].push_back(
        {{"type", gauge->type()},
         {"name", gauge->name()},
         {"base", array3(values.segment<3>(o + LengthGauge::kBaseIndex))},
         {"platform", array3(values.segment<3>(o + LengthGauge::kPlatformIndex))},
         {"offset", values[o + LengthGauge::kOffsetIndex]}});
  }
  out["free"] = Json::array();
  for (const int i : model.parameters().free_indices())
    out["free"].push_back(model.parameters()[i].name);
  return out;
}

std::shared_ptr<MeasurementModel> model_from_json(const Json& j, const std::string& source) {
  if (!j.is_object()) fail(source, "", "expected a JSON object (a kincal model file)");
  check_keys(j, source, "", {"format", "version", "units", "mechanism", "sensors", "free"});
  const Json& format = member(j, "format", source, "");
  if (format != kModelFormat)
    fail(source, "format",
         "expected \"" + std::string(kModelFormat) + "\", got " + json_excerpt(format));
  const Json& version = member(j, "version", source, "");
  if (version != kModelFormatVersion)
    fail(source, "version",
         "expected " + std::to_string(kModelFormatVersion) + ", got " + json_excerpt(version));
  const Json& units = member(j, "units", source, "");
  if (units != "mm") fail(source, "units", "expected \"mm\", got " + json_excerpt(units));

  const Json& mechanism = object_at(j, "mechanism", source, "");
  const std::string type = type_of(mechanism, source, "mechanism");
  if (type != "hexapod-6ups")
    fail(source, "mechanism.type",
         "expected \"hexapod-6ups\", got \"" + message_excerpt(type) + "\"");
  auto hexapod = hexapod_from_json(mechanism, source);

  const Json& sensors_json = member(j, "sensors", source, "");
  if (!sensors_json.is_array() || sensors_json.empty())
    fail(source, "sensors", "expected a non-empty array of sensor objects");
  std::vector<std::shared_ptr<const Sensor>> sensors;
  std::set<std::string> names;
  for (std::size_t s = 0; s < sensors_json.size(); ++s) {
    const std::string at = "sensors[" + std::to_string(s) + "]";
    if (!sensors_json[s].is_object()) fail(source, at, "expected a sensor object");
    const std::string sensor_type = type_of(sensors_json[s], source, at);
    if (sensor_type != "length-gauge")
      fail(source, at + ".type",
           "expected \"length-gauge\", got \"" + message_excerpt(sensor_type) + "\"");
    auto gauge = gauge_from_json(sensors_json[s], source, at);
    // The hexapod's actuators are columns leg1..leg6 and its parameters leg<i>.*: a sensor
    // named leg... could collide with either.
    if (gauge->name().rfind("leg", 0) == 0)
      fail(source, at + ".name",
           "'" + message_excerpt(gauge->name()) +
               "': names starting with 'leg' are reserved for the hexapod's legs; expected "
               "another name (e.g. gauge)");
    if (!names.insert(gauge->name()).second)
      fail(source, at + ".name",
           "'" + message_excerpt(gauge->name()) +
               "' is already used by another sensor; expected unique names");
    sensors.push_back(gauge);
  }
  auto model = std::make_shared<MeasurementModel>(hexapod, sensors);

  const Json& free = member(j, "free", source, "");
  if (!free.is_array()) fail(source, "free", "expected an array of parameter names or patterns");
  for (std::size_t k = 0; k < free.size(); ++k) {
    const std::string at = "free[" + std::to_string(k) + "]";
    if (!free[k].is_string()) fail(source, at, "expected a parameter name or pattern");
    try {
      model->parameters().set_free(free[k].get<std::string>(), true);
    } catch (const std::invalid_argument& e) {
      fail(source, at, message_excerpt(e.what(), 200));
    }
  }
  return model;
}

namespace {

// nlohmann's what() starts with "[json.exception.type_error.302] "; the reader needs only
// the rest.
std::string without_json_tag(const std::string& what) {
  const auto pos = what.find("] ");
  return pos == std::string::npos ? what : what.substr(pos + 2);
}

}  // namespace

std::shared_ptr<MeasurementModel> load_model(const std::string& path) {
  // Size and nesting limits, duplicate keys and malformed JSON: framework/json_input.hpp.
  const Json j = read_json_file(path, "model file");
  try {
    return model_from_json(j, path);
  } catch (const nlohmann::json::exception& e) {
    // model_from_json checks types before reading them; this is the net under that.
    throw std::invalid_argument(path + ": unexpected value: " + without_json_tag(e.what()));
  }
}

std::shared_ptr<MeasurementModel> model_with_values(const MeasurementModel& model,
                                                    const VectorXd& values) {
  return model_from_json(model_to_json(model, values), "(model)");
}

}  // namespace kincal
