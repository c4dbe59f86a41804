#pragma once
// The calibration report's page for people, rendered from the calibrate workflow's typed
// result (framework/workflows/calibrate.hpp), never from its JSON:
//
//   const kincal::CalibrateResult result = kincal::calibrate(request);
//   const std::string html = kincal::report::calibration_html(result);
//
// The page: the findings in plain language and what to do next, the summary, residuals per
// configuration and their histogram against the noise, parameter corrections with error bars,
// the correlation heat map, the singular-value spectrum with identifiability in words,
// outliers, the measured 3-D position error (a point-measuring sensor), the predicted pose
// accuracy over the workspace, and what the caller adds (CalibrationPageExtras). Every
// string from the result is escaped.

#include <optional>
#include <string>
#include <vector>

#include "kincal/framework/analysis/calibration_verdict.hpp"
#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"
#include "kincal/framework/analysis/image_views.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"
#include "kincal/framework/workflows/calibrate.hpp"

namespace kincal::report {

/// What a caller computed beside the workflow and the page shows.
struct CalibrationPageExtras {
  /// The target judged against the predicted pose error (judge_predicted_target): a finding
  /// and a line on the plots.
  std::optional<TargetJudgement> target;
  /// The sensitivity to the fixed parameters (fixed_parameter_sensitivity): a chart and a
  /// table.
  std::optional<SensitivityResult> sensitivity;
  /// Each camera's views (camera_view_checks, models/camera_start.hpp): a section with the
  /// reprojection error per view and every view drawn with its residual vectors.
  std::vector<ImageViews> image_views;
  /// The calibrated model file written with the report and its SHA-256 (empty: none).
  std::string calibrated_model_file, calibrated_model_sha256;
};

/// A least-determined parameter whose std exceeds this many times sigma_hat (same unit) is
/// one the data does not determine: a warning with the advice to fix it.
inline constexpr double kWeakParameterAmplification = 100;
/// Two estimates correlated at least this much (in absolute value) are a combination the
/// data determine, not two parameters.
inline constexpr double kCorrelatedPair = 0.999;

/// The page's findings, in order: the verdict's (result.verdict), then what the page adds
/// from the same result: the starts, conditioning, the least determined parameters, the
/// corrections within their std, correlations of +-1, outliers, rows dropped, the measured
/// and predicted position error, the target, what readings that measure no point cannot
/// show.
std::vector<Finding> calibration_page_findings(const CalibrateResult& result,
                                               const CalibrationPageExtras& extras = {});

/// The page (see the file's comment).
std::string calibration_html(const CalibrateResult& result,
                             const CalibrationPageExtras& extras = {});

}  // namespace kincal::report
