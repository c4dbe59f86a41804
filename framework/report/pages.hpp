#pragma once
// The pages for people of the other workflows, each rendered from what the workflow returned
// (framework/workflows/), never from its JSON: one self-contained HTML file each, every
// figure in a table with its unit or plotted, every string escaped. One file per page
// (validation_page.cpp, design_page.cpp, compare_page.cpp, observability_page.cpp); the
// calibration report's page is calibration_page.hpp.
//
//   const kincal::CompareResult result = kincal::compare_models(request);
//   const std::string html = kincal::report::compare_html(result);

#include <optional>
#include <string>

#include "kincal/framework/analysis/fixed_parameter_sensitivity.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"
#include "kincal/framework/workflows/compare.hpp"
#include "kincal/framework/workflows/design.hpp"
#include "kincal/framework/workflows/observability.hpp"
#include "kincal/framework/workflows/validate.hpp"

namespace kincal::report {

/// A held-out validation: the verdict in plain words (and against `target`, judged with
/// judge_measured_target), the residuals per reading against their prediction, the
/// chi-square check, the residuals per configuration plotted, and the 3-D position error
/// before and after calibration per configuration when the sensor measures a point (else
/// what the readings cannot show). `report_file` names the calibration report the prediction
/// came from (empty: none).
std::string validation_html(const ValidateRequest& request, const ValidateResult& result,
                            const std::string& report_file,
                            const std::optional<TargetJudgement>& target = std::nullopt);

/// An experiment design: what the design gains over a random one and over the nominal model
/// (and against `target`, judged with judge_predicted_target), the predicted pose error as a
/// table and over the workspace, the chosen configurations plotted among the candidates, the
/// criterion's progress over the exchange passes, the predicted parameter std, the
/// candidates and the exchange. `template_path` names the measurement template written.
std::string design_html(const ExperimentDesignResult& result, const std::string& template_path,
                        const std::optional<TargetJudgement>& target = std::nullopt);

/// A comparison with a known truth: the pose error in words, a plot of it per
/// configuration, the parameter errors as a plot and a table.
std::string compare_html(const CompareResult& result);

/// An identifiability analysis: findings on rank and conditioning, the singular values and
/// weakest combinations, the data/prior shares with a prior, what calibrate would keep, and
/// with `sensitivity` the fixed parameters' effect.
std::string observability_html(const ObservabilityResult& result,
                               const std::optional<SensitivityResult>& sensitivity = std::nullopt);

}  // namespace kincal::report
