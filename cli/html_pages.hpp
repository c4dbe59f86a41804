#pragma once
// The pages for people of `validate --html`, `design --html`, `compare --html` and
// `observability --html`, rendered from the commands' JSON results with the building blocks
// of cli/html_report.hpp (the calibration report has its own, larger page there), one file
// per page (html_validation_page.cpp, html_design_page.cpp, html_pages.cpp: compare,
// html_observability_page.cpp). No page shows a JSON object: every figure is in a table
// with its unit, or plotted.

#include <nlohmann/json.hpp>
#include <string>

namespace kincal::cli {

/// The page of a held-out validation (the JSON of `kincal validate --json`): the verdict in
/// plain words (and against --target), the residuals per reading against their prediction,
/// the chi-square check, the residuals per configuration plotted, and the 3-D position error
/// before and after calibration per configuration when the sensor measures a point (else
/// what the readings cannot show).
std::string render_validation_html(const nlohmann::ordered_json& validation);

/// The page of an experiment design (the JSON of `kincal design --json`): what the design
/// gains over a random one and over the nominal model (and against --target), the predicted
/// pose error as a table and over the workspace, the chosen configurations plotted among the
/// candidates, the criterion's progress over the exchange passes, the predicted parameter
/// std, the candidates and the exchange.
std::string render_design_html(const nlohmann::ordered_json& design);

/// The page of a comparison with a known truth (the JSON of `kincal compare --json`): the
/// pose error in words, a plot of it per configuration, the parameter errors as a plot and a
/// table.
std::string render_compare_html(const nlohmann::ordered_json& compare);

/// The page of an identifiability analysis (the JSON of `kincal observability --json`):
/// verdicts on rank and conditioning, the singular values and weakest combinations, the
/// data/prior shares with a prior, and with --sensitivity the fixed parameters' effect.
std::string render_observability_html(const nlohmann::ordered_json& observability);

}  // namespace kincal::cli
