#include "kincal/framework/extension/generic_model_file.hpp"

#include <stdexcept>

#include "kincal/framework/base/angles.hpp"

namespace kincal {

namespace {

using namespace json_field;

// How a "_deg" key is read; its writer picks the degrees that read back exactly.
double radians_of_degrees_key(double degrees) { return degrees / kDegreesPerRadian; }

/// One key of the object and the parameters it holds.
struct Key {
  enum Form { kNumber, kDegrees, kVector3, kFrame } form = kNumber;
  std::string key;  ///< as in the file ("tilt_deg" for kDegrees)
  int index = 0;    ///< first parameter
  bool optional = false;
};

// The keys of `layout`, in parameter order; std::logic_error when a group has no file form.
std::vector<Key> keys_of(const std::string& type, const ModelFileLayout& layout) {
  const auto& params = layout.parameters;
  std::vector<Key> keys;
  const int n = static_cast<int>(params.size());
  for (int i = 0; i < n;) {
    const std::string& name = params[i].name;
    const auto dot = name.rfind('.');
    Key k;
    k.index = i;
    if (dot == std::string::npos) {
      const bool angle = params[i].unit == "rad";
      k.form = angle ? Key::kDegrees : Key::kNumber;
      k.key = angle ? name + "_deg" : name;
      ++i;
    } else {
      const std::string group = name.substr(0, dot);
      std::vector<std::string> members;
      while (i < n && params[i].name.compare(0, dot + 1, group + ".") == 0 &&
             params[i].name.find('.', dot + 1) == std::string::npos)
        members.push_back(params[i++].name.substr(dot + 1));
      k.key = group;
      const std::vector<std::string> xyz = {"x", "y", "z"};
      const std::vector<std::string> frame = {"x", "y", "z", "rx", "ry", "rz"};
      if (members == xyz) {
        k.form = Key::kVector3;
      } else if (members == frame && params[k.index + 3].unit == "rad" &&
                 params[k.index + 4].unit == "rad" && params[k.index + 5].unit == "rad") {
        k.form = Key::kFrame;
      } else {
        throw std::logic_error("generic model file of '" + type + "': the parameters '" + group +
                               ".*' are neither x, y, z nor a frame x, y, z, rx, ry, rz; the "
                               "type needs its own reader and writer");
      }
    }
    k.optional = layout.optional_keys.count(k.key) > 0;
    keys.push_back(k);
  }
  for (const auto& optional : layout.optional_keys) {
    bool found = false;
    for (const Key& k : keys) found = found || k.key == optional;
    if (!found)
      throw std::logic_error("generic model file of '" + type + "': optional key '" + optional +
                             "' is not a key of its parameters");
  }
  return keys;
}

std::set<std::string> allowed_keys(const std::vector<Key>& keys, const ModelFileLayout& layout,
                                   bool named) {
  std::set<std::string> allowed = {"type"};
  if (named) allowed.insert("name");
  for (const Key& k : keys) allowed.insert(k.key);
  for (const auto& o : layout.options) allowed.insert(o.key);
  return allowed;
}

// The nominal values and options of `object`; defaults for absent optional keys.
VectorXd read_values(const Json& object, const JsonPath& where, const std::vector<Key>& keys,
                     const ModelFileLayout& layout, ModelFileOptions& options) {
  VectorXd values(static_cast<int>(layout.parameters.size()));
  for (int i = 0; i < values.size(); ++i) values[i] = layout.parameters[i].nominal;
  for (const Key& k : keys) {
    const Json* value = optional(object, k.key);
    if (!value) {
      if (k.optional) continue;
      member(object, k.key, where);  // fails: "missing key '...'"
    }
    const JsonPath at = where / k.key;
    switch (k.form) {
      case Key::kNumber:
        values[k.index] = number(*value, at);
        break;
      case Key::kDegrees:
        values[k.index] = radians_of_degrees_key(number(*value, at));
        break;
      case Key::kVector3:
        values.segment<3>(k.index) = vector3(*value, at);
        break;
      case Key::kFrame:
        values.segment<6>(k.index) = frame(*value, at);
        break;
    }
  }
  for (const auto& o : layout.options)
    options[o.key] = number_or(object, o.key, o.default_value, where);
  return values;
}

void write_values(Json& out, const std::vector<Key>& keys,
                  const Eigen::Ref<const VectorXd>& values) {
  for (const Key& k : keys) {
    switch (k.form) {
      case Key::kNumber:
        out[k.key] = values[k.index];
        break;
      case Key::kDegrees:
        out[k.key] = degrees_reading_back(values[k.index], values[k.index] * kDegreesPerRadian,
                                          radians_of_degrees_key) +
                     0.0;
        break;
      case Key::kVector3:
        out[k.key] = array3(values.segment<3>(k.index));
        break;
      case Key::kFrame:
        out[k.key] = pose_json(values.segment<3>(k.index), values.segment<3>(k.index + 3));
        break;
    }
  }
}

// The object built must have the layout's parameters: a mismatch is the type's bug.
template <class Made>
void check_made(const std::string& type, const Made* object, const ModelFileLayout& layout,
                const std::string& prefix) {
  if (!object)
    throw std::logic_error("generic model file of '" + type + "': make() returned nothing");
  const std::vector<Parameter>& made = object->parameters();
  bool same = made.size() == layout.parameters.size();
  for (std::size_t i = 0; same && i < made.size(); ++i)
    same = made[i].name == prefix + layout.parameters[i].name &&
           made[i].unit == layout.parameters[i].unit;
  if (!same)
    throw std::logic_error("generic model file of '" + type +
                           "': the object built does not have the parameters of its layout");
}

}  // namespace

ModelFileLayout sensor_layout(const Sensor& prototype, std::set<std::string> optional_keys,
                              std::vector<ModelFileOption> options) {
  ModelFileLayout layout;
  const std::string prefix = prototype.name() + ".";
  for (Parameter p : prototype.parameters()) {
    if (p.name.compare(0, prefix.size(), prefix) != 0)
      throw std::logic_error("sensor_layout: parameter '" + p.name + "' does not start with '" +
                             prefix + "'");
    p.name = p.name.substr(prefix.size());
    layout.parameters.push_back(std::move(p));
  }
  layout.optional_keys = std::move(optional_keys);
  layout.options = std::move(options);
  return layout;
}

SensorType generic_sensor_type(std::string type, std::string description, ModelFileLayout layout,
                               std::function<std::shared_ptr<const Sensor>(
                                   const std::string&, const VectorXd&, const ModelFileOptions&)>
                                   make,
                               std::function<ModelFileOptions(const Sensor&)> options_of) {
  const std::vector<Key> keys = keys_of(type, layout);
  SensorType t;
  t.type = type;
  t.description = std::move(description);
  t.read = [=](const Json& object, const JsonPath& where) {
    check_keys(object, where, allowed_keys(keys, layout, true));
    const std::string sensor_name = name(member(object, "name", where), where / "name");
    ModelFileOptions options;
    const VectorXd values = read_values(object, where, keys, layout, options);
    auto sensor = make(sensor_name, values, options);
    check_made(type, sensor.get(), layout, sensor_name + ".");
    return sensor;
  };
  t.write = [=](const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
    Json out = {{"name", sensor.name()}};
    write_values(out, keys, values);
    if (options_of)
      for (const auto& [key, value] : options_of(sensor)) out[key] = value;
    return out;
  };
  return t;
}

MechanismType generic_mechanism_type(
    std::string type, std::string description, ModelFileLayout layout,
    std::function<std::shared_ptr<const Mechanism>(const VectorXd&, const ModelFileOptions&)> make,
    std::function<ModelFileOptions(const Mechanism&)> options_of) {
  const std::vector<Key> keys = keys_of(type, layout);
  MechanismType t;
  t.type = type;
  t.description = std::move(description);
  t.read = [=](const Json& object, const JsonPath& where) {
    check_keys(object, where, allowed_keys(keys, layout, false));
    ModelFileOptions options;
    const VectorXd values = read_values(object, where, keys, layout, options);
    auto mechanism = make(values, options);
    check_made(type, mechanism.get(), layout, "");
    return mechanism;
  };
  t.write = [=](const Mechanism& mechanism, const Eigen::Ref<const VectorXd>& values) {
    Json out = Json::object();
    write_values(out, keys, values);
    if (options_of)
      for (const auto& [key, value] : options_of(mechanism)) out[key] = value;
    return out;
  };
  return t;
}

}  // namespace kincal
