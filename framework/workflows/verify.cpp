#include "kincal/framework/workflows/verify.hpp"

#include <stdexcept>

#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/sha256.hpp"
#include "kincal/framework/workflows/report_prediction.hpp"

namespace kincal {

VerifyResult verify_calibration(const std::string& report_file, const std::string& model_file) {
  JsonLimits limits;  // a report lists every residual: as large as validate reads
  limits.max_bytes = kMaxCalibrationReportBytes;
  const nlohmann::ordered_json report = read_json_file(report_file, "calibration report", limits);
  if (!report.is_object() || report.value("format", "") != "kincal-calibration-report")
    throw std::invalid_argument(report_file +
                                ": expected a calibration report (format "
                                "\"kincal-calibration-report\")");
  const auto entry = report.find("calibrated_model");
  if (entry == report.end() || entry->is_null())
    throw std::invalid_argument(
        report_file +
        ": names no calibrated model (calibrate ran without --out, or its solver did not reach a "
        "solution); nothing to check");
  if (!entry->is_object() || !entry->contains("file") || !(*entry)["file"].is_string() ||
      !entry->contains("sha256") || !(*entry)["sha256"].is_string())
    throw std::invalid_argument(report_file +
                                ": calibrated_model: expected {\"file\": ..., \"sha256\": ...}");
  VerifyResult result;
  result.report_file = report_file;
  result.model_file = model_file.empty() ? (*entry)["file"].get<std::string>() : model_file;
  result.expected_sha256 = (*entry)["sha256"].get<std::string>();
  result.sha256 = model_file_sha256(result.model_file);
  result.match = result.sha256 == result.expected_sha256;
  return result;
}

nlohmann::ordered_json verify_json(const VerifyResult& result) {
  return {{"format", "kincal-verify"},
          {"version", 1},
          {"report", result.report_file},
          {"model", result.model_file},
          {"match", result.match},
          {"sha256", result.sha256},
          {"expected_sha256", result.expected_sha256}};
}

std::string verify_mismatch_text(const VerifyResult& result) {
  return result.model_file + " is not the model " + result.report_file +
         " describes: its SHA-256 is " + result.sha256 + ", the report's " +
         result.expected_sha256 +
         " (a calibrate interrupted between writing the two leaves a new report beside an old "
         "model; run it again)";
}

}  // namespace kincal
