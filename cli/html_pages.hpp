#pragma once
// The pages for people of `validate --html`, `design --html` and `compare --html`, rendered from
// the commands' JSON results with the building blocks of cli/html_report.hpp (the calibration
// report has its own, larger page there).

#include <nlohmann/json.hpp>
#include <string>

namespace kincal::cli {

/// The page of a held-out validation (the JSON of `kincal validate --json`): the verdict in
/// plain words, the residuals per reading against their prediction, the chi-square check.
std::string render_validation_html(const nlohmann::ordered_json& validation);

/// The page of an experiment design (the JSON of `kincal design --json`): what the design
/// gains over a random one and over the nominal model, the predicted parameter std, the
/// candidates and the exchange.
std::string render_design_html(const nlohmann::ordered_json& design);

/// The page of a comparison with a known truth (the JSON of `kincal compare --json`): the
/// pose error in words, a plot of it per configuration, the parameter errors as a plot and a
/// table.
std::string render_compare_html(const nlohmann::ordered_json& compare);

}  // namespace kincal::cli
