#include "kincal/framework/calibration/frame_turns.hpp"

#include <cmath>

#include "kincal/framework/calibration/constrained_problem.hpp"

namespace kincal {

MatrixXd measurement_frame_turns(const CalibrationProblem& problem, const VectorXd& x) {
  const MeasurementModel& model = problem.model();
  const Measurements& data = problem.data();
  const int k = model.num_readings();
  // The first of each turning sensor's three readings in a configuration's reading vector.
  std::vector<int> firsts;
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const int index = model.sensors()[s]->frame_vector_reading_index();
    if (index < 0) continue;
    const int first = model.sensor_reading_offset(static_cast<int>(s)) + index;
    const VectorXd& std = model.reading_std();
    if (std[first + 1] != std[first] || std[first + 2] != std[first]) return {};
    for (int c = 0; c < data.size(); ++c)
      for (int a = 0; a < 3; ++a) {
        const double measured = data.readings(c, first + a);
        if (!std::isnan(measured) && measured != 0) return {};
      }
    firsts.push_back(first);
  }
  if (firsts.empty()) return {};
  VectorXd r;
  if (!problem.evaluate(x, &r, nullptr)) return {};
  MatrixXd turns = MatrixXd::Zero(r.size() + num_constraint_residuals(model), 3);
  for (int c = 0; c < data.size(); ++c)
    for (int first : firsts) {
      // A missing reading has a zero residual: it turns to zero.
      const Eigen::Index row = static_cast<Eigen::Index>(c) * k + first;
      const Vector3d v = r.segment<3>(row);
      for (int a = 0; a < 3; ++a) turns.block<3, 1>(row, a) = Vector3d::Unit(a).cross(v);
    }
  return turns;
}

}  // namespace kincal
