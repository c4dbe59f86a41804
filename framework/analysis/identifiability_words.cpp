#include "kincal/framework/analysis/identifiability_words.hpp"

#include <algorithm>
#include <cstdio>

namespace kincal {

namespace {

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string parameter_words(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  if (dot == std::string::npos) return name;
  const std::string prefix = name.substr(0, dot), component = name.substr(dot + 1);
  if (component == "offset") return prefix + "'s zero offset";
  std::string part = prefix + "'s";
  if (prefix == "base")
    part = "the base frame";
  else if (prefix == "tool")
    part = "the tool frame";
  else if (ends_with(prefix, ".origin"))
    part = prefix.substr(0, prefix.size() - 7) + "'s origin";
  else if (ends_with(prefix, ".frame"))
    part = prefix.substr(0, prefix.size() - 6) + "'s frame";
  else if (ends_with(prefix, ".target"))
    part = "the target point of " + prefix.substr(0, prefix.size() - 7);
  else if (ends_with(prefix, ".marker"))
    part = "the marker of " + prefix.substr(0, prefix.size() - 7);
  else if (prefix.find('.') != std::string::npos)  // "leg1.platform" -> "leg1's platform"
    part = prefix.substr(0, prefix.rfind('.')) + "'s " + prefix.substr(prefix.rfind('.') + 1);
  if (component.size() == 1) return part + ", shift along " + component;
  if (component.size() == 2 && component[0] == 'r')
    return part + ", rotation about " + component.substr(1);
  return part + ", " + component;
}

std::string describe_dependent(const DependentParameter& d, const MeasurementModel& model) {
  const std::string effect = dependent_effect(d, model);
  return d.name + " (" + parameter_words(d.name) + ")" +
         (effect.rfind("moves", 0) == 0 ? " " : ": ") + effect;
}

std::string fixed_parameters_table(const std::vector<std::string>& names,
                                   const std::vector<std::string>& effects) {
  std::size_t name_width = 9, words_width = 8;  // "parameter", "in words"
  std::vector<std::string> words;
  for (const std::string& name : names) {
    words.push_back(parameter_words(name));
    name_width = std::max(name_width, name.size());
    words_width = std::max(words_width, words.back().size());
  }
  auto pad = [](std::string text, std::size_t width) {
    text.resize(std::max(text.size(), width), ' ');
    return text;
  };
  std::string out = "fixed at their model values, not identifiable from this data (" +
                    std::to_string(names.size()) + "), with what each duplicates:\n";
  out += "  " + pad("parameter", name_width) + "  " + pad("in words", words_width) +
         "  what the data see of it\n";
  for (std::size_t i = 0; i < names.size(); ++i)
    out += "  " + pad(names[i], name_width) + "  " + pad(words[i], words_width) + "  " +
           (i < effects.size() ? effects[i] : std::string("not determined")) + "\n";
  return out;
}

std::string dependent_effect(const DependentParameter& d, const MeasurementModel& model) {
  std::string text;
  if (d.unseen) {
    text = "no reading depends on it";
    const int index = model.parameters().find(d.name);
    if (ends_with(d.name, ".offset") && index >= 0 && model.parameters()[index].unit == "rad")
      text += " (the measured point lies on " + d.name.substr(0, d.name.size() - 7) + "'s axis)";
    else if (ends_with(d.name, ".rx") || ends_with(d.name, ".ry") || ends_with(d.name, ".rz"))
      text += " (it turns the measured point about itself)";
    return text;
  }
  // A turn of the measurement frame changes no fit: a gauge freedom (docs/theory.md).
  const std::string turn = " a turn of the whole setup, which changes no fit (a gauge freedom)";
  if (d.equivalent.empty()) return d.turn ? "moves the readings only as" + turn : "not determined";
  text = "moves the readings as";
  char buf[32];
  for (std::size_t k = 0; k < d.equivalent.size() && k < 4; ++k) {
    std::snprintf(buf, sizeof buf, "%+.3g", d.equivalent[k].second);
    text += std::string(k ? " and" : "") + " " + buf + " x " + d.equivalent[k].first;
  }
  if (d.equivalent.size() > 4) text += " and " + std::to_string(d.equivalent.size() - 4) + " more";
  if (d.turn) text += " and" + turn;
  return text;
}

std::vector<int> choose_identifiable(const MeasurementModel& model, const std::vector<int>& free,
                                     const MatrixXd& J, const IdentifiabilityOptions& options,
                                     const MatrixXd& turns) {
  std::vector<int> priority;
  const std::vector<int> all = model.identification_priority();
  if (!all.empty())
    for (int index : free) priority.push_back(all[static_cast<std::size_t>(index)]);
  return identifiable_subset(J, priority, options, turns);
}

}  // namespace kincal
