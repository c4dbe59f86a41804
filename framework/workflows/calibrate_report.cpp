#include "kincal/framework/workflows/calibrate_report.hpp"

#include "kincal/framework/analysis/starts_report.hpp"

namespace kincal {

std::string calibration_text(const CalibrateResult& result, const std::string& extra_text) {
  const std::string geometry_only =
      result.geometry_only ? geometry_only_text(*result.geometry_only) + "\n" : "";
  return to_text(result.report) + starts_text(result.starts) + extra_text + geometry_only +
         to_text(result.verdict);
}

nlohmann::ordered_json calibration_json(const CalibrateResult& result,
                                        const nlohmann::ordered_json& extra) {
  nlohmann::ordered_json out = to_json(result.report);
  out["starts"] = starts_json(result.starts);
  if (extra.is_object())
    for (const auto& [key, value] : extra.items()) out[key] = value;
  if (result.geometry_only) out["geometry_only_export"] = geometry_only_json(*result.geometry_only);
  out["verdict"] = to_json(result.verdict);
  if (!result.null_directions.empty()) out["null_directions"] = result.null_directions;
  return out;
}

}  // namespace kincal
