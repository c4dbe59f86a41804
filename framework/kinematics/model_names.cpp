#include "kincal/framework/kinematics/model_names.hpp"

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal {

namespace {

std::string described(const std::string& what, const std::string& name,
                      const std::string& problem) {
  return problem.empty() ? "" : what + " '" + message_excerpt(name) + "' " + problem;
}

}  // namespace

std::string model_name_problem(const MeasurementModel& model) {
  std::string problem;
  const auto check = [&problem](const std::string& what, const std::string& name, NameKind kind) {
    if (problem.empty()) problem = described(what, name, name_problem(name, kind));
    return problem.empty();
  };
  const Mechanism& mechanism = model.mechanism();
  check("mechanism type", mechanism.type(), NameKind::kName);
  for (const std::string& name : mechanism.actuator_names())
    check("actuator", name, NameKind::kColumn);
  for (const auto& sensor : model.sensors()) {
    check("sensor type", sensor->type(), NameKind::kName);
    check("sensor", sensor->name(), NameKind::kName);
  }
  for (const std::string& name : model.reading_names()) check("reading", name, NameKind::kColumn);
  for (const Parameter& p : model.parameters().all()) check("parameter", p.name, NameKind::kColumn);
  for (const auto& constraint : model.constraints()) {
    check("constraint type", constraint->type(), NameKind::kName);
    if (problem.empty())
      problem =
          described("constraint label", constraint->label(), text_problem(constraint->label()));
  }
  return problem;
}

}  // namespace kincal
