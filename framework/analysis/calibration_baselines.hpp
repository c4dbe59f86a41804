#pragma once
// The baselines a calibration is judged against, into its report: the nominal geometry with
// only the measured point located (an imported arm's reflector), registration only (the
// frames of the sensor, the base and the tool fitted, the geometry nominal), and with folds,
// K-fold cross-validation of the calibration and of registration only (cross_validation.hpp).
// The verdict (calibration_verdict.hpp) reads them: a calibration worse than its registration
// baseline, in sample or held out, is not loaded.

#include <memory>
#include <vector>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/least_squares/solver.hpp"

namespace kincal {

/// Fills report.point_located, report.registration and (folds > 0) report.cross_validation
/// for the free parameters `free` of `model` fitted to `data` from `start` with `solver` and
/// `solver_options` (verbosity off), under the model's prior when `with_prior`. Each baseline
/// fits only the parameters of its set that the data determine (id_options). A baseline that
/// cannot be computed says why (why_not) or is left out; nothing throws for a failed fit.
void add_calibration_baselines(CalibrationReport& report,
                               const std::shared_ptr<const MeasurementModel>& model,
                               const Measurements& data, const VectorXd& start,
                               const std::vector<int>& free, const Solver& solver,
                               const SolverOptions& solver_options, bool with_prior, int folds,
                               const IdentifiabilityOptions& id_options);

}  // namespace kincal
