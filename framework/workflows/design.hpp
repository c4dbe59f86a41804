#pragma once
// The design workflow: which configurations (and, with several sensors, which sensor
// placements) to measure, chosen by a criterion from random candidates in the actuators' box,
// with what the design predicts (parameter stds and pose errors, against a random design of
// the same size and the nominal spread) and, optionally, a bound on how good any design of
// these candidates can be. What `kincal design` does between reading its files and writing
// the template, as one library call.
//
//   kincal::ExperimentDesignRequest request;
//   request.model = model;                    // free mask, prior_std, actuator ranges
//   request.noise_std = model->reading_std(); // or per reading
//   request.options.count = 40;
//   const kincal::ExperimentDesignResult r = kincal::design_experiment(request);
//   write(kincal::design_template_csv(r));    // the configurations to measure

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/design/experiment_design.hpp"

namespace kincal {

struct ExperimentDesignRequest {
  /// The model: its free mask, prior_std and actuator ranges (the candidates' box). Not
  /// modified.
  std::shared_ptr<const MeasurementModel> model;
  /// count, criterion, candidates, seed, singularity margin, orientation length; its monitor
  /// sees every step and may stop the work (Ctrl-C): the best design so far, marked partial.
  DesignOptions options;
  /// The readings' noise std, one per reading (empty: the model's reading_std, which it must
  /// state); where it comes from, in words ("--noise-std", "reading_std").
  VectorXd noise_std;
  std::string noise_source = "the model's reading_std";
  /// Data already measured: its readings count as information and the design adds to them.
  std::optional<Measurements> existing;
  /// Also bound how good any design of these candidates can be (D, A, I).
  bool bound = false;
  /// When even all the candidates cannot determine every free parameter: stop (kStop), or
  /// design for the identifiable subset, the others fixed at their model values with a note
  /// (kFixDependent: what calibrate does for an arm imported from a URDF; choose it with
  /// when_rank_deficient, framework/analysis/identifiability_check.hpp).
  WhenRankDeficient when_rank_deficient = WhenRankDeficient::kStop;
  /// In messages and the template: the model file (empty: "the model"), and how the face
  /// spells its options ("--" for the program, "" for Python).
  std::string model_file;
  std::string option_prefix = "--";
  /// Called with each note as it arises (they are in the result as well).
  std::function<void(const std::string&)> on_note;
};

struct ExperimentDesignResult {
  /// Stopped while drawing candidates, with fewer than asked for: nothing else was done (the
  /// program writes nothing and exits 130).
  bool stopped_before_design = false;
  DesignOptions options;
  DesignSetup setup;
  DesignCandidates candidates;
  DesignResult design;
  DesignBound bound;
  bool partial = false;     ///< stopped early: the best design found so far
  std::string stopped_in;   ///< the stage it stopped in ("exchange pass 2")
  double std_ratio = 0;     ///< against the bound (design_std_ratio_to_bound), NaN without one
  Measurements rows;        ///< the configurations to measure (design_rows)
  std::vector<int> random;  ///< a random design of the same size, compared with
  MatrixXd designed_cov, random_cov;
  PoseErrorPrediction designed_pose, random_pose, nominal_pose;
  std::string noise_source, model_file;
  std::vector<std::string> free_names;
  /// The free parameters the candidates cannot determine, fixed for the design
  /// (when_rank_deficient kFixDependent); empty otherwise.
  std::vector<std::string> fixed_for_design;
  std::shared_ptr<const MeasurementModel> model;
  std::vector<std::string> notes;
};

/// Runs the workflow. Throws std::invalid_argument for a design that cannot be made: no free
/// parameter, no noise std, fewer reachable candidates than asked for, fewer readings than
/// free parameters, candidates (or the chosen ones) that cannot determine every free
/// parameter, a criterion that is not finite.
ExperimentDesignResult design_experiment(const ExperimentDesignRequest& request);

/// The program's renderings: the text report (`template_path` names the template file in
/// it), the JSON report (`target`, when not null, is the program's --target section), and the
/// measurement template (CSV: comments, header, one row per configuration, empty readings).
std::string design_text(const ExperimentDesignResult& result, const std::string& template_path);
nlohmann::ordered_json design_json(const ExperimentDesignResult& result,
                                   const std::string& template_path,
                                   const nlohmann::ordered_json& target);
std::string design_template_csv(const ExperimentDesignResult& result);
/// What the criterion measures, in words.
std::string criterion_meaning(DesignCriterion criterion, double orientation_length);

}  // namespace kincal
