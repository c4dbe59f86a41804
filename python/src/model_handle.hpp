#pragma once
// What a kincal.Model holds: its own measurement model (Python may change its free mask) and
// where it came from.

#include <memory>
#include <string>

#include "kincal/framework/kinematics/measurement_model.hpp"

namespace kincal::python {

struct ModelHandle {
  std::shared_ptr<MeasurementModel> model;
  std::string source;
  ModelHandle copy() const { return {std::make_shared<MeasurementModel>(*model), source}; }
};

}  // namespace kincal::python
