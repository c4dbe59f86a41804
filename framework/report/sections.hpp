#pragma once
// Sections shared by several pages for people, each from a typed result: the identifiability
// analysis (calibration and observability), the predicted pose error over the workspace
// (calibration and design), the sensitivity to fixed parameters (calibration and
// observability with --sensitivity) and the finding on a --target (calibration, validation,
// design). HTML with inline SVG charts, every string escaped.

#include <optional>
#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"
#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/analysis/image_views.hpp"
#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"

namespace kincal::report {

/// The singular-value chart, rank and conditioning in words (kIllConditioned,
/// kSeverelyIllConditioned), the weakest combinations.
std::string identifiability_html(const Identifiability& id);

/// One prediction shown in the pose-accuracy table and plot, with its column label.
struct PredictionColumn {
  std::string label;
  const PoseErrorPrediction* prediction = nullptr;
};

/// The table of a predicted pose error over `samples` workspace configurations (one column
/// per prediction: calibrated and nominal, or designed, random and nominal) and the plot of
/// the error at every sample, sorted; `target` (null: none) is drawn as a line.
std::string pose_accuracy_html(int samples, const std::vector<PredictionColumn>& columns,
                               const TargetJudgement* target);

/// For each fixed parameter, the pose error an error in it leaves after calibrating the free
/// ones, as a bar chart and a table; `target_mm` (NaN: none) is drawn as a line.
std::string sensitivity_html(const SensitivityResult& sensitivity, double target_mm);

/// A camera's views (framework/analysis/image_views.hpp): the reprojection error overall and
/// per view in a table, and each view drawn at its image's proportions, on its thumbnail when
/// there is one, with the points measured and their residual vectors (measured to predicted)
/// magnified by one factor for every view, stated above them.
std::string image_views_html(const ImageViews& views);

/// The finding on a target: good when met, do-not-load when not, a note when it could not be
/// judged.
Finding target_finding(const TargetJudgement& target);

}  // namespace kincal::report
