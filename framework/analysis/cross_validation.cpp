#include "kincal/framework/analysis/cross_validation.hpp"

#include <stdexcept>

#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/prior_problem.hpp"

namespace kincal {

Fit fit_parameters(std::shared_ptr<const MeasurementModel> model, const Measurements& data,
                   const VectorXd& start, const std::vector<int>& free, const Solver& solver,
                   const SolverOptions& options, bool with_prior) {
  const CalibrationProblem problem(model, data, start, free);
  VectorXd x = problem.initial_free_parameters();
  const Prior prior = with_prior ? model_prior(problem) : Prior{};
  Fit fit;
  fit.summary = solve_calibration(solver, problem, prior, x, options, Formulation::kNested).summary;
  fit.values = fit.ok() ? problem.full_parameters(x) : start;
  return fit;
}

CrossValidation cross_validate(std::shared_ptr<const MeasurementModel> model,
                               const Measurements& data, const VectorXd& start,
                               const std::vector<int>& free, int folds, const Solver& solver,
                               const SolverOptions& options, bool with_prior) {
  if (folds < 2 || folds > data.size())
    throw std::invalid_argument("expected 2 <= folds <= " + std::to_string(data.size()) +
                                " (the configurations)");
  CrossValidation cv;
  cv.folds = folds;
  cv.residuals = MatrixXd::Constant(data.size(), model->num_readings(), NAN);
  for (int f = 0; f < folds; ++f) {
    std::vector<int> held_out;
    for (int r = f; r < data.size(); r += folds) held_out.push_back(r);
    const Measurements training = drop_rows(data, held_out);
    const Fit fit = fit_parameters(model, training, start, free, solver, options, with_prior);
    if (!fit.ok()) {
      if (cv.failed_folds++ == 0) cv.failure = fit.summary.message;
      continue;
    }
    Measurements test;
    test.actuators.resize(static_cast<int>(held_out.size()), data.actuators.cols());
    test.readings.resize(static_cast<int>(held_out.size()), data.readings.cols());
    for (std::size_t i = 0; i < held_out.size(); ++i) {
      test.actuators.row(static_cast<int>(i)) = data.actuators.row(held_out[i]);
      test.readings.row(static_cast<int>(i)) = data.readings.row(held_out[i]);
    }
    try {
      const MatrixXd r = residual_matrix(model, test, fit.values);
      for (std::size_t i = 0; i < held_out.size(); ++i)
        cv.residuals.row(held_out[i]) = r.row(static_cast<int>(i));
    } catch (const std::runtime_error& e) {
      if (cv.failed_folds++ == 0) cv.failure = e.what();
    }
  }
  return cv;
}

}  // namespace kincal
