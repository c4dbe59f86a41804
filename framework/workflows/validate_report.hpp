#pragma once
// The validate workflow's result as people read it (text) and as programs read it (JSON,
// format "kincal-validation"): what `kincal validate` prints and writes with --json, and
// what its HTML page is rendered from.

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/framework/workflows/validate.hpp"

namespace kincal {

/// The text report, one finding per line, ending in "\n"; `model_name` and `data_name` are
/// the inputs as shown to the reader (the program quotes unprintable characters).
std::string validation_text(const ValidateRequest& request, const ValidateResult& result,
                            const std::string& model_name, const std::string& data_name);

/// The JSON report. `report_file` names the calibration report the prediction came from
/// (empty: null); `target`, when not null, is the --target section, placed before the
/// residuals.
nlohmann::ordered_json validation_json(const ValidateRequest& request, const ValidateResult& result,
                                       const std::string& report_file,
                                       const nlohmann::ordered_json& target);

}  // namespace kincal
