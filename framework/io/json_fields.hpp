#pragma once
// Reading model-file JSON with messages that say where: every helper takes a JsonPath
// ("<file>: mechanism.joints[2].a") and throws std::invalid_argument
// "<file>: <path>: <what was expected>" on anything else. Mechanism and sensor readers
// (registered in the ModelRegistry) build on these, so that every model type reports bad
// input the same way.

#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "kincal/framework/kinematics/pose.hpp"

namespace kincal {

using Json = nlohmann::ordered_json;

/// A position in a JSON document, for messages.
class JsonPath {
 public:
  JsonPath(std::string source, std::string path = "")
      : source_(std::move(source)), path_(std::move(path)) {}
  JsonPath operator/(const std::string& key) const;
  JsonPath operator[](std::size_t index) const;
  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }
  /// Throws std::invalid_argument "<source>: <path>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string source_, path_;
};

namespace json_field {

/// Typos such as "fre" or "ofset" must not pass silently: any key outside `allowed` fails.
void check_keys(const Json& object, const JsonPath& where, const std::set<std::string>& allowed);
/// The object at `where`; fails unless `value` is an object.
const Json& object(const Json& value, const JsonPath& where);
/// object[key], which must exist.
const Json& member(const Json& object, const std::string& key, const JsonPath& where);
/// object[key] or nullptr when absent.
const Json* optional(const Json& object, const std::string& key);
double number(const Json& value, const JsonPath& where);
/// object[key] as a number, or `fallback` when absent.
double number_or(const Json& object, const std::string& key, double fallback,
                 const JsonPath& where);
std::string string(const Json& value, const JsonPath& where);
/// A name that is a CSV column and a parameter-name prefix, within kincal's name policy
/// (framework/kinematics/names.hpp: name_problem).
std::string name(const Json& value, const JsonPath& where);
Vector3d vector3(const Json& value, const JsonPath& where);
/// {"position": [x, y, z] (mm), "rotation_zyx_deg": [rx, ry, rz]}, R = Rz(rz) Ry(ry) Rx(rx).
Pose pose(const Json& value, const JsonPath& where);
/// The same object as frame parameters [x, y, z, rx, ry, rz] (mm, rad; frame_from_parameters):
/// the angles as written, not extracted again from a rotation matrix, so that a frame
/// parameter block read and written back (pose_json(position, rx_ry_rz)) keeps its digits.
Vector6d frame(const Json& value, const JsonPath& where);

/// The conversion pose() and frame() read "rotation_zyx_deg" with: degrees * (pi / 180).
double radians_from_degrees(double degrees);
/// The number of degrees to write for an angle of `radians` so that `to_radians`, the
/// reader's conversion, gives `radians` back bit for bit: `degrees` (the writer's product)
/// when it does, else the nearest of its neighbours within 4 ulps that does. An angle that
/// was read from a file always has one (the number read), so a model read and written reads
/// back unchanged (degrees -> radians -> degrees -> radians need not: fuzz_model_file found
/// 191.99999999999999 deg, whose product with 180/pi reads back 1 ulp away); an angle that
/// no number of degrees converts to exactly (a computed one) is written as `degrees`.
double degrees_reading_back(double radians, double degrees, double (*to_radians)(double));

/// [x, y, z], with -0 written as 0.
Json array3(const Vector3d& v);
/// The form pose() reads.
Json pose_json(const Pose& pose);
/// A pose from position and Z-Y-X Euler angles in radians (rx, ry, rz): the form of
/// frame parameters (x, y, z, rx, ry, rz).
Json pose_json(const Vector3d& position, const Vector3d& rx_ry_rz);

}  // namespace json_field
}  // namespace kincal
