#pragma once
// The sections of the calibration report's page (render_calibration_html, cli/html_report.hpp),
// each from the report's JSON: HTML with inline SVG charts, every string escaped. The
// identifiability section, shared with the observability page, is in html_report.hpp.

#include <nlohmann/json.hpp>
#include <string>

namespace kincal::cli {

/// Residuals per configuration with +-sigma_hat and the outlier threshold, and their
/// histogram against the noise; one pair of charts per reading unit (or one, weighted).
std::string calibration_residuals_html(const nlohmann::ordered_json& r);
/// The corrections with error bars per unit (angles in mrad) and the parameter table.
std::string calibration_parameters_html(const nlohmann::ordered_json& r);
/// The correlation heat map.
std::string calibration_correlation_html(const nlohmann::ordered_json& r);
/// The model's parameter-only constraints (e.g. a known distance between two sockets): each
/// one's residual at the estimate against its stated std. Empty when there are none.
std::string calibration_constraints_html(const nlohmann::ordered_json& r);
/// The flagged configurations and their residuals.
std::string calibration_outliers_html(const nlohmann::ordered_json& r);
/// Files, solver, outcome, residual RMS/max, sigma_hat, the calibrated model's SHA-256.
std::string calibration_summary_html(const nlohmann::ordered_json& r);

}  // namespace kincal::cli
