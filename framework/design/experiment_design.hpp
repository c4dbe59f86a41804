#pragma once
// Experiment design: which configurations (and, for a model with several sensors, which
// sensor placements) to measure so that a calibration determines the parameters, or the
// poses, best for a given number of measurements.
//
// Everything is linearised at the nominal parameters (the truth is unknown before
// measuring). A measurement contributes its whitened rows x (readings / noise std, free
// columns of the reading Jacobian) to the information matrix M = M0 + sum x x^T, where M0
// holds the prior (diag 1 / prior_std^2), the model's parameter-only constraints (a known
// distance between fixtures) and data already measured (--existing). Parameters are normalised by
// their nominal spread s (prior_std, or e / sqrt(3) of the simulated error), so that mm and rad mix
// and criterion values are unit-free:
//   D: maximise log det M         (the volume of the confidence ellipsoid; scale-free),
//   A: minimise trace(M^-1) / n   (mean variance, relative to the nominal spread^2),
//   E: maximise lambda_min(M)     (the worst-determined direction),
//   I: minimise trace(W M^-1)     (W = mean J_pos^T J_pos + L^2 J_rot^T J_rot over workspace
//                                  samples: the mean predicted position variance over the
//                                  workspace, mm^2, plus the orientation's at length L).
// The choice is a modified Fedorov exchange (Cook and Nachtsheim 1980) started from a greedy
// design: for each chosen measurement in turn, remove it and add the best candidate (which
// may be itself), until a pass changes nothing. Removing and adding are rank-one updates of
// M^-1 and of every candidate's quadratic forms x^T M^-1 x (and x^T M^-1 W M^-1 x for A and
// I), so a pass costs a few matrix-vector products over the candidates per measurement.

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"

namespace kincal {

enum class DesignCriterion { kD, kA, kE, kI };

/// Where a design is, for a caller that shows progress or may stop it: `stage` is
/// "candidates" (drawn so far of `total`), "greedy" (measurements picked of `total`),
/// "exchange" (measurements of the pass `pass` revisited of `total`) or "bound" (iterations
/// of at most `total`).
struct DesignStep {
  const char* stage = "";
  long done = 0, total = 0;
  int pass = 0;
};
/// Called between steps; returning false asks the work to stop early with what it has: the
/// candidates drawn so far, the exchange's best design so far (the greedy start is always
/// finished), the bound certified so far. DesignResult::stopped / DesignCandidates::stopped /
/// DesignBound::stopped say so.
using DesignMonitor = std::function<bool(const DesignStep&)>;
const char* to_string(DesignCriterion criterion);
/// "D", "A", "E", "I" (also lower case); throws std::invalid_argument otherwise.
DesignCriterion parse_design_criterion(const std::string& text);

struct DesignOptions {
  DesignCriterion criterion = DesignCriterion::kD;
  int count = 30;               ///< measurements to choose
  int num_random = 10000;       ///< random candidate configurations (besides the corners)
  std::uint64_t seed = 1;       ///< candidates, workspace samples and the random baseline
  int workspace_samples = 200;  ///< for criterion I and the predicted pose error
  /// Criterion I weighs the pose error |dp|^2 + (L dtheta)^2 with this L (mm per rad, the
  /// length at which a rotation error counts as much as a position error: e.g. the tool's
  /// reach); 0 = position only.
  double orientation_length = 0;
  /// A configuration is a candidate when its singularity margin (see singularity_margin) is
  /// at least this.
  double min_singularity_margin = 0.5;
  /// The candidates' box per actuator, [box_low, box_high] (its corners and uniform draws in
  /// it); both empty: centre ± the model's actuator ranges, or, where every commanded
  /// actuator has limits and the ranges are the mechanism's defaults, the limits (a serial
  /// arm's region is where it can go, not a small box around its zero). Any box is clipped
  /// to the actuators' limits.
  VectorXd box_low, box_high;
  /// The configuration the box of the actuator ranges is centred on; empty: home.
  VectorXd centre;
  /// Candidate configurations given (rows x actuators), used instead of drawing any: each is
  /// still kept only where forward kinematics converges, the margin holds and a sensor reads.
  MatrixXd given;
  int max_passes = 50;  ///< exchange passes at most (a pass that changes nothing stops)
  /// Per reading noise std (the reading's unit); empty: the model's reading_std().
  VectorXd noise_std;
  /// Parameter spread for simulated errors without prior_std (nominal_parameter_std).
  double default_error_mm = 5, default_error_rad = 0.01;
  /// Progress and early stop (empty: none).
  DesignMonitor monitor;
};

/// How far a configuration is from a singular one, relative to home: kappa^-1(q) /
/// kappa^-1(home), where kappa^-1 = s_min / s_max is the inverse condition number of the
/// actuator-to-pose Jacobian d pose / d q (Mechanism::pose_jacobian_actuators), its
/// columns scaled by the actuator ranges and its rotation rows by the length that gives the
/// translation and rotation blocks equal norms at home. 1 = as well conditioned as home, 0 =
/// singular.
class SingularityGauge {
 public:
  /// Throws std::invalid_argument when the home pose is unreachable.
  SingularityGauge(const MeasurementModel& model, const VectorXd& params);
  /// The margin at q whose pose (reached with the gauge's parameters) is `pose`; 0 when
  /// d pose / d q cannot be computed there (singular, or forward kinematics fails nearby).
  double margin(const ActuatorsRef& q, const Pose& pose) const;
  const VectorXd& home_actuators() const { return home_; }

 private:
  double inverse_condition(const ActuatorsRef& q, const Pose& pose) const;
  /// d pose / d q of the actuators that move (range > 0), columns scaled by the ranges;
  /// false when it cannot be computed at q.
  bool actuator_jacobian(const ActuatorsRef& q, const Pose& pose, Matrix6Xd& J) const;
  const MeasurementModel& model_;
  VectorXd params_, home_;
  double rotation_length_ = 1, home_inverse_condition_ = 1;
};

/// Candidate measurements: a configuration, read by one sensor (a model with several
/// sensors: each (configuration, sensor) pair is a candidate, so that design chooses the
/// placements too) or by its only sensor.
struct DesignCandidates {
  MatrixXd configurations;       ///< reachable candidate configurations x num_actuators
  VectorXd margins;              ///< their singularity margins
  int num_corners = 0;           ///< the first configurations are the box's corners
  int rejected_unreachable = 0;  ///< drawn configurations forward kinematics fails at
  int rejected_singular = 0;     ///< drawn configurations below the singularity margin
  /// Drawn configurations in which no sensor takes a reading (a camera's target out of view).
  int rejected_unseen = 0;
  std::vector<int> configuration;  ///< per candidate: its configuration (row)
  std::vector<int> sensor;         ///< per candidate: its sensor (index in the model)
  /// Per candidate: the readings its sensor takes there (fewer than the sensor has where it
  /// can miss some: a camera's points out of view).
  std::vector<int> readings;
  /// Candidate c owns rows row_offset[c] .. row_offset[c + 1]: one per reading, or, for a
  /// sensor with more readings than free parameters (a camera), the n rows of the triangular
  /// factor R of the readings' information (X^T X = R^T R).
  std::vector<int> row_offset;
  MatrixXd rows;         ///< normalised whitened information rows, all candidates
  bool stopped = false;  ///< the monitor stopped the draw: fewer than asked for
  /// Where the candidates come from, for the report: "given", "the box given",
  /// "the joint limits", "home ± the actuator ranges", "the centre ± the actuator ranges"
  /// (", clipped to the joint limits" when the limits cut the box).
  std::string region;
  VectorXd region_low, region_high;  ///< the box drawn from (empty when given)
  int size() const { return static_cast<int>(sensor.size()); }
};

/// What the criteria need besides the candidates, in normalised parameters.
struct DesignSetup {
  std::vector<int> free_indices;
  VectorXd scale;             ///< nominal spread of each free parameter (normalisation)
  VectorXd noise_std;         ///< per reading, the reading's unit
  MatrixXd base_information;  ///< M0: prior + the model's constraints + existing data (normalised)
  int constraint_rows = 0;    ///< rows of the model's parameter-only constraints in M0
  bool has_prior = false;
  int existing_readings = 0;   ///< readings of the existing data that enter M0
  WorkspaceSamples workspace;  ///< at the nominal parameters
  MatrixXd workspace_weight;   ///< W (normalised) of criterion I
};

/// The setup for `model` (its free mask and prior_std) with `existing` data (may be null;
/// its rows must be reachable at the nominal values: only present readings count).
DesignSetup make_design_setup(const MeasurementModel& model, const DesignOptions& options,
                              const Measurements* existing);

/// The candidates: the 2^num_actuators corners of the configuration box (when there are at
/// most 2^12 of them) and options.num_random uniform draws in it (or the configurations of
/// options.given), all at the nominal values, kept when forward kinematics converges and the
/// singularity margin holds.
DesignCandidates make_design_candidates(const MeasurementModel& model, const DesignSetup& setup,
                                        const DesignOptions& options);

struct DesignResult {
  std::vector<int> chosen;     ///< candidate indices, in the order of the output
  double criterion_value = 0;  ///< D: log det M, A: trace M^-1 / n, E: lambda_min, I: trace W M^-1
  double greedy_value = 0;     ///< the same for the greedy start
  int passes = 0, exchanges = 0;
  std::vector<double> pass_values;  ///< the criterion after each exchange pass (its progress)
  bool stopped = false;  ///< the monitor stopped the exchange: the best design found so far
};

/// Chooses options.count candidates (without repeats) by options.criterion. Throws
/// std::invalid_argument when there are fewer candidates than asked for.
DesignResult choose_design(const DesignCandidates& candidates, const DesignSetup& setup,
                           const DesignOptions& options);

/// How good any design of options.count candidates (without repeats) can be: a bound on the
/// criterion from the continuous relaxation, weights 0 <= w_c <= 1 summing to count in place
/// of the 0/1 choice. The relaxed criterion is convex (D: concave), so Frank-Wolfe iterations
/// from `start` (a design, e.g. the exchange's) give at each step a certified bound, the
/// relaxed value minus the duality gap. E is not smooth: its bound is NaN.
struct DesignBound {
  /// D: no design's log det M exceeds it; A, I: no design's value is below it.
  double bound = std::numeric_limits<double>::quiet_NaN();
  double relaxed_value = std::numeric_limits<double>::quiet_NaN();  ///< of the best weights
  int iterations = 0;
  bool stopped = false;  ///< the monitor stopped the iterations: the bound certified so far
};
DesignBound design_bound(const DesignCandidates& candidates, const DesignSetup& setup,
                         const DesignOptions& options, const std::vector<int>& start,
                         int max_iterations = 200, double relative_gap = 1e-4);

/// The criterion's efficiency against the bound, as a ratio of parameter (D) or pose (I, A)
/// standard deviations: how much larger they are than the best any design could give, >= 1.
/// D: exp((bound - value) / (2 n)) (the geometric mean of the confidence ellipsoid's axes);
/// A, I: sqrt(value / bound). NaN without a bound.
double design_std_ratio_to_bound(DesignCriterion criterion, double value, const DesignBound& bound,
                                 int num_free);

/// `count` candidates drawn uniformly without repeats among the random (non-corner) ones:
/// the paper's design, for comparison.
std::vector<int> random_design(const DesignCandidates& candidates, int count, std::uint64_t seed);

/// The information matrix of the setup plus the chosen candidates (normalised), its
/// criterion value, and the covariance of the free parameters in their units (M^-1 scaled
/// back; NaN when M is singular).
MatrixXd design_information(const DesignCandidates& candidates, const std::vector<int>& chosen,
                            const DesignSetup& setup);
double criterion_value(DesignCriterion criterion, const MatrixXd& information,
                       const DesignSetup& setup);
MatrixXd design_covariance(const MatrixXd& information, const DesignSetup& setup);

/// The chosen configurations as a measurement table: one row per distinct configuration, the
/// readings of the sensors chosen there set to 0 and the others NaN (missing), as are the
/// readings a sensor would not take there (a camera's points out of view).
Measurements design_rows(const MeasurementModel& model, const DesignCandidates& candidates,
                         const std::vector<int>& chosen);

/// Everything above in one call: setup, candidates, the exchange and the template rows.
struct DesignRun {
  DesignSetup setup;
  DesignCandidates candidates;
  DesignResult result;
  Measurements rows;  ///< design_rows of the result
};
DesignRun run_design(const MeasurementModel& model, const DesignOptions& options,
                     const Measurements* existing = nullptr);

}  // namespace kincal
