// The fixture-distance constraint in model files (models/fixture_distance.hpp), in the
// top-level "constraints" array:
//   { "type": "fixture-distance", "between": ["socket0", "socket1"], "distance": 50,
//     "std": 0.05 }

#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/fixture_distance.hpp"

namespace kincal {

namespace {

std::shared_ptr<const ParameterConstraint> read_fixture_distance(const Json& j,
                                                                 const JsonPath& where,
                                                                 const MeasurementModel& model) {
  json_field::check_keys(j, where, {"type", "between", "distance", "std"});
  const JsonPath between_at = where / "between";
  const Json& between = json_field::member(j, "between", where);
  if (!between.is_array() || between.size() != 2)
    between_at.fail("expected two sensor names, e.g. [\"socket0\", \"socket1\"]");
  std::string names[2];
  for (int i = 0; i < 2; ++i) {
    names[i] = json_field::string(between[i], between_at[i]);
    for (const auto& parameter : fixture_point_names(names[i]))
      if (model.parameters().find(parameter) < 0)
        between_at[i].fail("'" + message_excerpt(names[i]) +
                           "' is no sensor with a fixture point; expected the name of a sensor "
                           "with parameters <name>.point.{x,y,z} (a socket)");
  }
  const double distance =
      json_field::number(json_field::member(j, "distance", where), where / "distance");
  const double std = json_field::number(json_field::member(j, "std", where), where / "std");
  try {
    return std::make_shared<FixtureDistance>(names[0], names[1], distance, std);
  } catch (const std::invalid_argument& e) {
    where.fail(e.what());
  }
}

Json write_fixture_distance(const ParameterConstraint& constraint) {
  const auto& c = dynamic_cast<const FixtureDistance&>(constraint);
  return {{"between", {c.a(), c.b()}}, {"distance", c.distance()}, {"std", c.std()}};
}

}  // namespace

void register_fixture_distance(ModelRegistry& registry) {
  registry.add_constraint({"fixture-distance",
                           "a known distance (mm) between two sensors' fixture points (two "
                           "sockets), with its std; one residual |p_a - p_b| - d",
                           read_fixture_distance, write_fixture_distance});
}

}  // namespace kincal
