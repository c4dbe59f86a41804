#pragma once
// What a kinematic export leaves out. A URDF or a DH table holds a mechanism's geometry, not
// its non-geometric parameters (a joint's compliance under gravity: Mechanism::
// non_geometric_parameters): a controller that loads only the exported geometry misses their
// effect. Measured here at the calibration's own configurations, so that the report can say
// by how much: the readings with every parameter at the estimate, against the same with the
// non-geometric ones at zero.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

struct GeometryOnlyEffect {
  int configurations = 0;
  /// Per configuration, the distance between the length readings (mm) with and without the
  /// non-geometric parameters: mean and max over the configurations.
  double mean = 0, max = 0;
  std::string unit = "mm";
  /// The non-geometric parameters, by name.
  std::vector<std::string> parameters;
};

/// Nothing when the model's mechanism has no non-geometric parameter, all of them are zero
/// at `values`, or no configuration of `data` can be predicted.
std::optional<GeometryOnlyEffect> geometry_only_effect(const MeasurementModel& model,
                                                       const VectorXd& values,
                                                       const Measurements& data);

/// "a kinematic export (URDF, DH) holds the geometry only: loading it alone leaves the ..."
std::string geometry_only_text(const GeometryOnlyEffect& effect);
nlohmann::ordered_json geometry_only_json(const GeometryOnlyEffect& effect);

}  // namespace kincal
