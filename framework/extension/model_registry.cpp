#include "kincal/framework/extension/model_registry.hpp"

#include <stdexcept>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

namespace {

template <class Entry, class Name>
const Entry& find(const std::vector<Entry>& entries, const std::string& wanted, Name name_of,
                  const char* what) {
  std::string known;
  for (const auto& e : entries) {
    if (name_of(e) == wanted) return e;
    known += (known.empty() ? "" : ", ") + name_of(e);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + message_excerpt(wanted) +
                              "' (available: " + known + ")");
}

template <class Entry, class Name>
void require_new(const std::vector<Entry>& entries, const std::string& name, Name name_of,
                 const char* what) {
  if (name.empty()) throw std::logic_error(std::string(what) + " registered without a name");
  for (const auto& e : entries)
    if (name_of(e) == name)
      throw std::logic_error(std::string(what) + " '" + name + "' registered twice");
}

}  // namespace

ModelRegistry& ModelRegistry::global() {
  static ModelRegistry registry = [] {
    ModelRegistry r;
    register_builtin_models(r);
    return r;
  }();
  return registry;
}

void ModelRegistry::add_mechanism(MechanismType type) {
  require_new(
      mechanisms_, type.type, [](const MechanismType& t) { return t.type; }, "mechanism type");
  if (!type.read || !type.write)
    throw std::logic_error("mechanism type '" + type.type + "' needs a reader and a writer");
  mechanisms_.push_back(std::move(type));
}

void ModelRegistry::add_sensor(SensorType type) {
  require_new(
      sensors_, type.type, [](const SensorType& t) { return t.type; }, "sensor type");
  if (!type.read || !type.write)
    throw std::logic_error("sensor type '" + type.type + "' needs a reader and a writer");
  sensors_.push_back(std::move(type));
}

void ModelRegistry::add_constraint(ConstraintType type) {
  require_new(
      constraints_, type.type, [](const ConstraintType& t) { return t.type; }, "constraint type");
  if (!type.read || !type.write)
    throw std::logic_error("constraint type '" + type.type + "' needs a reader and a writer");
  constraints_.push_back(std::move(type));
}

void ModelRegistry::add_preset(ModelPreset preset) {
  require_new(
      presets_, preset.name, [](const ModelPreset& p) { return p.name; }, "preset");
  if (!preset.make) throw std::logic_error("preset '" + preset.name + "' needs a factory");
  presets_.push_back(std::move(preset));
}

void ModelRegistry::add_export_format(ExportFormat format) {
  if (format.format.empty() || format.mechanism_type.empty())
    throw std::logic_error("export format registered without a format or mechanism type name");
  if (format.format == "urdf" || format.format == "csv" || format.format == "json")
    throw std::logic_error("export format '" + format.format + "' is kincal's own");
  if (export_format(format.mechanism_type, format.format))
    throw std::logic_error("export format '" + format.format + "' of mechanism type '" +
                           format.mechanism_type + "' registered twice");
  if (!format.write) throw std::logic_error("export format '" + format.format + "' needs a writer");
  export_formats_.push_back(std::move(format));
}

const ExportFormat* ModelRegistry::export_format(const std::string& mechanism_type,
                                                 const std::string& format) const {
  for (const auto& f : export_formats_)
    if (f.mechanism_type == mechanism_type && f.format == format) return &f;
  return nullptr;
}

const MechanismType& ModelRegistry::mechanism(const std::string& type) const {
  return find(
      mechanisms_, type, [](const MechanismType& t) { return t.type; }, "mechanism type");
}

const SensorType& ModelRegistry::sensor(const std::string& type) const {
  return find(
      sensors_, type, [](const SensorType& t) { return t.type; }, "sensor type");
}

const ConstraintType& ModelRegistry::constraint(const std::string& type) const {
  return find(
      constraints_, type, [](const ConstraintType& t) { return t.type; }, "constraint type");
}

const ModelPreset& ModelRegistry::preset(const std::string& name) const {
  return find(
      presets_, name, [](const ModelPreset& p) { return p.name; }, "model preset");
}

std::shared_ptr<MeasurementModel> ModelRegistry::make_preset(const std::string& name) const {
  return preset(name).make();
}

}  // namespace kincal
