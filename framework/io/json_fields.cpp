#include "kincal/framework/io/json_fields.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

JsonPath JsonPath::operator/(const std::string& key) const {
  // Keys come from files: a 60 KB key must not become a 60 KB message.
  const std::string shown = message_excerpt(key);
  return JsonPath(source_, path_.empty() ? shown : path_ + "." + shown);
}

JsonPath JsonPath::operator[](std::size_t index) const {
  return JsonPath(source_, path_ + "[" + std::to_string(index) + "]");
}

void JsonPath::fail(const std::string& what) const {
  throw std::invalid_argument(source_ + ": " + (path_.empty() ? "" : path_ + ": ") + what);
}

namespace json_field {

void check_keys(const Json& object, const JsonPath& where, const std::set<std::string>& allowed) {
  for (const auto& item : object.items()) {
    if (allowed.count(item.key())) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    where.fail("unknown key '" + message_excerpt(item.key()) + "' (expected " + list + ")");
  }
}

const Json& object(const Json& value, const JsonPath& where) {
  if (!value.is_object()) where.fail("expected an object, got " + json_excerpt(value));
  return value;
}

const Json& member(const Json& object, const std::string& key, const JsonPath& where) {
  const auto it = object.find(key);
  if (it == object.end()) where.fail("missing key '" + key + "'");
  return *it;
}

const Json* optional(const Json& object, const std::string& key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

double number(const Json& value, const JsonPath& where) {
  if (!value.is_number()) where.fail("expected a number, got " + json_excerpt(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) where.fail("expected a finite number");
  return v;
}

double number_or(const Json& object, const std::string& key, double fallback,
                 const JsonPath& where) {
  const Json* value = optional(object, key);
  return value ? number(*value, where / key) : fallback;
}

std::string string(const Json& value, const JsonPath& where) {
  if (!value.is_string()) where.fail("expected a string, got " + json_excerpt(value));
  return value.get<std::string>();
}

std::string name(const Json& value, const JsonPath& where) {
  if (!value.is_string()) where.fail("expected a name (a string), got " + json_excerpt(value));
  const std::string text = value.get<std::string>();
  const std::string problem = name_problem(text);
  if (!problem.empty())
    where.fail("expected a name within kincal's name policy, got " + json_excerpt(value) +
               ", which " + problem);
  return text;
}

Vector3d vector3(const Json& value, const JsonPath& where) {
  if (!value.is_array() || value.size() != 3)
    where.fail("expected an array of 3 numbers [x, y, z], got " + json_excerpt(value));
  Vector3d v;
  for (int a = 0; a < 3; ++a) v[a] = number(value[a], where[a]);
  return v;
}

Pose pose(const Json& value, const JsonPath& where) {
  object(value, where);
  check_keys(value, where, {"position", "rotation_zyx_deg"});
  Pose pose;
  pose.translation = vector3(member(value, "position", where), where / "position");
  const Vector3d deg =
      vector3(member(value, "rotation_zyx_deg", where), where / "rotation_zyx_deg");
  pose.rotation = rotation_from_euler_zyx(Vector3d(
      radians_from_degrees(deg[2]), radians_from_degrees(deg[1]), radians_from_degrees(deg[0])));
  return pose;
}

Vector6d frame(const Json& value, const JsonPath& where) {
  object(value, where);
  check_keys(value, where, {"position", "rotation_zyx_deg"});
  Vector6d frame;
  frame.head<3>() = vector3(member(value, "position", where), where / "position");
  const Vector3d deg =
      vector3(member(value, "rotation_zyx_deg", where), where / "rotation_zyx_deg");
  for (int a = 0; a < 3; ++a) frame[3 + a] = radians_from_degrees(deg[a]);
  return frame;
}

double radians_from_degrees(double degrees) { return degrees * kRadiansPerDegree; }

double degrees_reading_back(double radians, double degrees, double (*to_radians)(double)) {
  if (to_radians(degrees) == radians) return degrees;
  double up = degrees, down = degrees;
  for (int step = 0; step < 4; ++step) {
    up = std::nextafter(up, std::numeric_limits<double>::infinity());
    if (to_radians(up) == radians) return up;
    down = std::nextafter(down, -std::numeric_limits<double>::infinity());
    if (to_radians(down) == radians) return down;
  }
  return degrees;
}

// "+ 0.0" turns -0 into 0 so that files do not show "-0.0".
Json array3(const Vector3d& v) { return Json::array({v[0] + 0.0, v[1] + 0.0, v[2] + 0.0}); }

Json pose_json(const Vector3d& position, const Vector3d& rx_ry_rz) {
  Vector3d deg;
  for (int a = 0; a < 3; ++a)
    deg[a] =
        degrees_reading_back(rx_ry_rz[a], rx_ry_rz[a] * kDegreesPerRadian, radians_from_degrees);
  return {{"position", array3(position)}, {"rotation_zyx_deg", array3(deg)}};
}

Json pose_json(const Pose& pose) {
  const Vector3d zyx = euler_zyx(pose.rotation);  // (alpha, beta, gamma) = (rz, ry, rx)
  return pose_json(pose.translation, Vector3d(zyx[2], zyx[1], zyx[0]));
}

}  // namespace json_field
}  // namespace kincal
