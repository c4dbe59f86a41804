#include "kincal/framework/workflows/calibrate_report.hpp"

#include "kincal/framework/analysis/starts_report.hpp"

namespace kincal {

std::string calibration_text(const CalibrateResult& result, const std::string& extra_text) {
  return to_text(result.report) + starts_text(result.starts) + extra_text + to_text(result.verdict);
}

nlohmann::ordered_json calibration_json(const CalibrateResult& result,
                                        const nlohmann::ordered_json& extra) {
  nlohmann::ordered_json out = to_json(result.report);
  out["starts"] = starts_json(result.starts);
  if (extra.is_object())
    for (const auto& [key, value] : extra.items()) out[key] = value;
  out["verdict"] = to_json(result.verdict);
  if (!result.null_directions.empty()) out["null_directions"] = result.null_directions;
  return out;
}

}  // namespace kincal
