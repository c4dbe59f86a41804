#include "kincal/models/model_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/kinematics/model_names.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

namespace {

using json_field::check_keys;
using json_field::member;

std::string type_of(const Json& j, const JsonPath& where) {
  json_field::object(j, where);
  return json_field::string(member(j, "type", where), where / "type");
}

// {"<pattern>": value, ...}: per-parameter or per-actuator settings given by glob patterns.
void for_each_pattern(
    const Json& j, const JsonPath& where,
    const std::function<void(const std::string&, double, const JsonPath&)>& apply) {
  json_field::object(j, where);
  for (const auto& item : j.items()) {
    const JsonPath at = where / item.key();
    const double value = json_field::number(item.value(), at);
    if (value < 0) at.fail("expected a value >= 0");
    try {
      apply(item.key(), value, at);
    } catch (const std::invalid_argument& e) {
      at.fail(e.what());
    }
  }
}

// Readings and actuators share the columns of a measurement file.
// Every column of the model's measurement files, whatever type made it (a registered type's
// own names included), within the name policy (framework/kinematics/names.hpp), so that every file
// kincal writes with these names reads back, and unique.
void check_columns(const MeasurementModel& model, const JsonPath& where) {
  const auto check = [](const std::string& name, const JsonPath& at) {
    const std::string problem = name_problem(name, NameKind::kColumn);
    if (!problem.empty()) at.fail("column '" + message_excerpt(name) + "' " + problem);
  };
  std::set<std::string> columns;
  for (const auto& name : model.mechanism().actuator_names()) {
    check(name, where / "mechanism");
    columns.insert(name);
  }
  for (std::size_t s = 0; s < model.sensors().size(); ++s)
    for (const auto& name : model.sensors()[s]->reading_names()) {
      check(name, (where / "sensors")[s]);
      if (!columns.insert(name).second)
        (where / "sensors")[s].fail("reading '" + name +
                                    "' has the name of an actuator or of another reading; "
                                    "expected a different sensor name");
    }
}

}  // namespace

Json model_to_json(const MeasurementModel& model, const VectorXd& values) {
  if (values.size() != model.num_parameters())
    throw std::invalid_argument("model_to_json: " + std::to_string(values.size()) +
                                " values for a model with " +
                                std::to_string(model.num_parameters()) + " parameters");
  // JSON has no infinity or NaN (nlohmann would write null), and a model file holds finite
  // numbers only: what is written must read back.
  for (int i = 0; i < model.num_parameters(); ++i)
    if (!std::isfinite(values[i]))
      throw std::invalid_argument("parameter '" + model.parameters()[i].name + "': value " +
                                  (std::isnan(values[i])     ? "nan"
                                   : std::signbit(values[i]) ? "-inf"
                                                             : "inf") +
                                  "; a model file holds finite numbers only");
  const ModelRegistry& registry = ModelRegistry::global();
  const Mechanism& mechanism = model.mechanism();
  Json out;
  out["format"] = kModelFormat;
  out["version"] = kModelFormatVersion;
  out["units"] = "mm";
  Json mechanism_json = {{"type", mechanism.type()}};
  mechanism_json.update(registry.mechanism(mechanism.type())
                            .write(mechanism, values.head(mechanism.num_parameters())));
  out["mechanism"] = mechanism_json;
  out["sensors"] = Json::array();
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const Sensor& sensor = *model.sensors()[s];
    Json sensor_json = {{"type", sensor.type()}};
    sensor_json.update(
        registry.sensor(sensor.type())
            .write(sensor, values.segment(model.sensor_parameter_offset(static_cast<int>(s)),
                                          sensor.num_parameters())));
    out["sensors"].push_back(sensor_json);
  }
  if (!model.constraints().empty()) {
    out["constraints"] = Json::array();
    for (const auto& constraint : model.constraints()) {
      Json constraint_json = {{"type", constraint->type()}};
      constraint_json.update(registry.constraint(constraint->type()).write(*constraint));
      out["constraints"].push_back(constraint_json);
    }
  }
  out["free"] = Json::array();
  for (const int i : model.parameters().free_indices())
    out["free"].push_back(model.parameters()[i].name);
  // Settings that differ from the defaults, so that a file read back simulates the same.
  Json param_error = Json::object();
  for (const auto& p : model.parameters().all())
    if (!std::isnan(p.error_half_width)) param_error[p.name] = p.error_half_width;
  if (!param_error.empty()) out["param_error"] = param_error;
  Json prior_std = Json::object();
  for (const auto& p : model.parameters().all())
    if (p.has_prior()) prior_std[p.name] = p.prior_std;
  if (!prior_std.empty()) out["prior_std"] = prior_std;
  Json config_range = Json::object();
  for (int i = 0; i < mechanism.num_actuators(); ++i)
    if (model.actuator_ranges()[i] != mechanism.actuators()[i].default_range)
      config_range[mechanism.actuators()[i].name] = model.actuator_ranges()[i];
  if (!config_range.empty()) out["config_range"] = config_range;
  Json reading_std = Json::object();
  const auto reading_names = model.reading_names();
  for (int i = 0; i < model.num_readings(); ++i)
    if (model.reading_std()[i] != 1.0) reading_std[reading_names[i]] = model.reading_std()[i];
  if (!reading_std.empty()) out["reading_std"] = reading_std;
  return out;
}

std::string calibrated_model_text(MeasurementModel model, const VectorXd& values,
                                  const std::vector<std::string>& fixed) {
  for (const auto& name : fixed) model.parameters().set_free(name, false);
  return model_to_json(model, values).dump(2) + "\n";
}

std::shared_ptr<MeasurementModel> model_from_json(const Json& j, const std::string& source) {
  const JsonPath root(source);
  if (!j.is_object()) root.fail("expected a JSON object (a kincal model file)");
  check_keys(j, root,
             {"format", "version", "units", "mechanism", "sensors", "free", "param_error",
              "prior_std", "config_range", "reading_std", "constraints"});
  const Json& format = member(j, "format", root);
  if (format != kModelFormat)
    (root / "format")
        .fail("expected \"" + std::string(kModelFormat) + "\", got " + json_excerpt(format));
  const Json& version = member(j, "version", root);
  if (version != kModelFormatVersion)
    (root / "version")
        .fail("expected " + std::to_string(kModelFormatVersion) + ", got " + json_excerpt(version));
  const Json& units = member(j, "units", root);
  if (units != "mm")
    (root / "units")
        .fail("expected \"mm\" (lengths in mm; angles in keys ending _deg), got " +
              json_excerpt(units));

  const ModelRegistry& registry = ModelRegistry::global();
  const JsonPath mechanism_at = root / "mechanism";
  const Json& mechanism_json = member(j, "mechanism", root);
  const std::string type = type_of(mechanism_json, mechanism_at);
  const MechanismType* mechanism_type = nullptr;
  try {
    mechanism_type = &registry.mechanism(type);
  } catch (const std::invalid_argument& e) {
    (mechanism_at / "type").fail(e.what());
  }
  auto mechanism = mechanism_type->read(mechanism_json, mechanism_at);

  const JsonPath sensors_at = root / "sensors";
  const Json& sensors_json = member(j, "sensors", root);
  if (!sensors_json.is_array() || sensors_json.empty())
    sensors_at.fail("expected a non-empty array of sensor objects");
  std::vector<std::shared_ptr<const Sensor>> sensors;
  std::set<std::string> names;
  for (std::size_t s = 0; s < sensors_json.size(); ++s) {
    const JsonPath at = sensors_at[s];
    const std::string sensor_type = type_of(sensors_json[s], at);
    const SensorType* entry = nullptr;
    try {
      entry = &registry.sensor(sensor_type);
    } catch (const std::invalid_argument& e) {
      (at / "type").fail(e.what());
    }
    auto sensor = entry->read(sensors_json[s], at);
    if (!names.insert(sensor->name()).second)
      (at / "name")
          .fail("'" + message_excerpt(sensor->name()) +
                "' is already used by another sensor; expected unique names");
    sensors.push_back(sensor);
  }
  std::shared_ptr<MeasurementModel> model;
  try {
    model = std::make_shared<MeasurementModel>(mechanism, sensors);
  } catch (const std::invalid_argument& e) {
    // e.g. a sensor whose parameter names collide with the mechanism's.
    sensors_at.fail(std::string(e.what()) + "; expected a different sensor name");
  }
  check_columns(*model, root);
  if (const Json* constraints = json_field::optional(j, "constraints")) {
    const JsonPath constraints_at = root / "constraints";
    if (!constraints->is_array()) constraints_at.fail("expected an array of constraint objects");
    for (std::size_t k = 0; k < constraints->size(); ++k) {
      const JsonPath at = constraints_at[k];
      const std::string constraint_type = type_of((*constraints)[k], at);
      const ConstraintType* entry = nullptr;
      try {
        entry = &registry.constraint(constraint_type);
      } catch (const std::invalid_argument& e) {
        (at / "type").fail(e.what());
      }
      auto constraint = entry->read((*constraints)[k], at, *model);
      try {
        model->add_constraint(std::move(constraint));
      } catch (const std::invalid_argument& e) {
        at.fail(e.what());  // a type whose reader let through a parameter the model lacks
      }
    }
  }
  // The other names the types made (parameters, sensors, constraint labels; a plug-in's
  // type may make any): the same policy.
  const std::string bad_name = model_name_problem(*model);
  if (!bad_name.empty()) root.fail(bad_name);

  const Json& free = member(j, "free", root);
  if (!free.is_array()) (root / "free").fail("expected an array of parameter names or patterns");
  for (std::size_t k = 0; k < free.size(); ++k) {
    const JsonPath at = (root / "free")[k];
    if (!free[k].is_string()) at.fail("expected a parameter name or pattern");
    try {
      model->parameters().set_free(free[k].get<std::string>(), true);
    } catch (const std::invalid_argument& e) {
      at.fail(message_excerpt(e.what(), 200));
    }
  }
  if (const Json* param_error = json_field::optional(j, "param_error"))
    for_each_pattern(*param_error, root / "param_error",
                     [&](const std::string& pattern, double value, const JsonPath&) {
                       model->parameters().for_each_matching(
                           pattern, [value](Parameter& p) { p.error_half_width = value; });
                     });
  if (const Json* prior_std = json_field::optional(j, "prior_std"))
    for_each_pattern(
        *prior_std, root / "prior_std",
        [&](const std::string& pattern, double value, const JsonPath&) {
          if (!(value >= kMinPriorStd && value <= kMaxPriorStd))  // for_each_pattern names where
            throw std::invalid_argument(
                "expected a prior std between 1e-150 and 1e150 (omit it for no prior)");
          model->parameters().for_each_matching(pattern,
                                                [value](Parameter& p) { p.prior_std = value; });
        });
  if (const Json* reading_std = json_field::optional(j, "reading_std"))
    for_each_pattern(*reading_std, root / "reading_std",
                     [&](const std::string& pattern, double value, const JsonPath&) {
                       model->set_reading_std(pattern, value);
                     });
  if (const Json* config_range = json_field::optional(j, "config_range"))
    for_each_pattern(*config_range, root / "config_range",
                     [&](const std::string& pattern, double value, const JsonPath&) {
                       model->set_actuator_range(pattern, value);
                     });
  return model;
}

namespace {

// nlohmann's what() starts with "[json.exception.type_error.302] "; the reader needs only
// the rest.
std::string without_json_tag(const std::string& what) {
  const auto pos = what.find("] ");
  return pos == std::string::npos ? what : what.substr(pos + 2);
}

std::shared_ptr<MeasurementModel> model_from_parsed_json(const Json& j, const std::string& source) {
  try {
    return model_from_json(j, source);
  } catch (const nlohmann::json::exception& e) {
    // model_from_json checks types before reading them; this is the net under that.
    throw std::invalid_argument(source + ": unexpected value: " + without_json_tag(e.what()));
  }
}

}  // namespace

std::shared_ptr<MeasurementModel> load_model(const std::string& path) {
  // Size and nesting limits, duplicate keys and malformed JSON: framework/io/json_input.hpp.
  return model_from_parsed_json(read_json_file(path, "model file"), path);
}

std::shared_ptr<MeasurementModel> model_from_text(const std::string& text,
                                                  const std::string& source) {
  return model_from_parsed_json(parse_json_text(text, source), source);
}

std::shared_ptr<MeasurementModel> model_with_values(const MeasurementModel& model,
                                                    const VectorXd& values) {
  return model_from_json(model_to_json(model, values), "(model)");
}

}  // namespace kincal
