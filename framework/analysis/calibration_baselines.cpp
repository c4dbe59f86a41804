// The baselines a calibration is judged against (calibration_baselines.hpp).

#include "kincal/framework/analysis/calibration_baselines.hpp"

#include <stdexcept>

#include "kincal/framework/analysis/cross_validation.hpp"
#include "kincal/framework/analysis/position_error.hpp"
#include "kincal/framework/calibration/frame_turns.hpp"

namespace kincal {

void add_calibration_baselines(CalibrationReport& report,
                               const std::shared_ptr<const MeasurementModel>& model,
                               const Measurements& data, const VectorXd& start,
                               const std::vector<int>& free, const Solver& solver,
                               const SolverOptions& solver_options, bool with_prior, int folds,
                               const IdentifiabilityOptions& id_options) {
  SolverOptions options = solver_options;
  options.verbosity = 0;  // the iterations shown are the calibration's
  // Only the parameters of `subset` the data determine (a point's orientation is unseen).
  const auto determined = [&](std::vector<int> subset) {
    const CalibrationProblem probe(model, data, start, subset);
    MatrixXd J;
    if (!probe.evaluate(probe.initial_free_parameters(), nullptr, &J)) return subset;
    std::vector<int> kept;
    // Nor a turn of the whole setup, which changes no fit (sockets; J has no constraint rows).
    MatrixXd turns = measurement_frame_turns(probe, probe.initial_free_parameters());
    if (turns.cols()) turns = turns.topRows(J.rows()).eval();
    for (int i : identifiable_subset(J, id_options, turns)) kept.push_back(subset[i]);
    return kept;
  };
  // The nominal geometry with the measured point located: "before" as a user means it when
  // the model did not know where the reflector is (an imported arm's starts at the flange).
  const std::vector<int> point = measured_point_indices(*model, free);
  if (measures_position(*model) && !point.empty() && point.size() < free.size()) {
    const std::vector<int> located = determined(point);
    const Fit fit = fit_parameters(model, data, start, located, solver, options, with_prior);
    if (fit.ok()) {
      try {
        const MatrixXd r = residual_matrix(model, data, fit.values);
        report.point_located.residual_rms = residual_rms_by_unit(*model, r);
        report.point_located.position = summarize_position_errors(position_errors(*model, r));
        report.point_located.termination = to_string(fit.summary.termination);
        for (int i : located) report.point_located.names.push_back(model->parameters()[i].name);
        report.point_located.computed = !located.empty();
      } catch (const std::runtime_error&) {
        // Not computable at the located point: no such line in the report.
      }
    }
  }
  std::vector<int> registration = registration_indices(*model, free);
  auto& baseline = report.registration;
  if (registration.empty()) {
    baseline.why_not = "no free parameter is a frame of the sensor, the base or the tool";
  } else if (registration.size() == free.size()) {
    baseline.why_not = "every free parameter is a frame: the calibration is a registration";
  } else {
    registration = determined(registration);
    const Fit fit = fit_parameters(model, data, start, registration, solver, options, with_prior);
    baseline.termination = to_string(fit.summary.termination);
    if (!fit.ok()) {
      baseline.why_not = "the registration-only fit did not converge (" + fit.summary.message + ")";
    } else {
      try {
        const MatrixXd r = residual_matrix(model, data, fit.values);
        baseline.residual_rms = residual_rms_by_unit(*model, r);
        baseline.position = summarize_position_errors(position_errors(*model, r));
        baseline.computed = true;
        for (int i : registration) baseline.names.push_back(model->parameters()[i].name);
      } catch (const std::runtime_error& e) {
        baseline.why_not =
            std::string("the registration-only fit cannot predict the data (") + e.what() + ")";
      }
    }
  }
  if (folds == 0) return;
  auto& cv = report.cross_validation;
  const CrossValidation full =
      cross_validate(model, data, start, free, folds, solver, options, with_prior);
  cv.folds = folds;
  cv.failed = full.failed_folds;
  cv.failure = full.failure;
  cv.residual_rms = residual_rms_by_unit(*model, full.residuals);
  cv.position = summarize_position_errors(position_errors(*model, full.residuals));
  if (baseline.computed) {
    const CrossValidation reg =
        cross_validate(model, data, start, registration, folds, solver, options, with_prior);
    if (reg.failed_folds && !cv.failed) cv.failure = "registration only: " + reg.failure;
    cv.failed += reg.failed_folds;
    cv.registration_residual_rms = residual_rms_by_unit(*model, reg.residuals);
    cv.registration_position = summarize_position_errors(position_errors(*model, reg.residuals));
  }
}

}  // namespace kincal
