#pragma once
// Whether a calibrated model file is the one a calibration report was written with
// (`kincal verify`, kincal.verify). calibrate writes the two files one after the other, so a
// crash between the two renames can leave a new report beside an old model; the report
// records the SHA-256 of its model, and this compares it.

#include <nlohmann/json.hpp>
#include <string>

namespace kincal {

struct VerifyResult {
  std::string report_file;
  /// The model file checked: the one given, or the one the report names.
  std::string model_file;
  std::string sha256;           ///< of the model file's bytes
  std::string expected_sha256;  ///< the report's calibrated_model.sha256
  bool match = false;
};

/// Reads the calibration report `report_file` and hashes `model_file` ("" = the file the
/// report names). Throws std::invalid_argument, one line naming the file, for a file that is
/// not a calibration report, a report naming no model, or an unreadable model file.
VerifyResult verify_calibration(const std::string& report_file, const std::string& model_file);

/// {"format": "kincal-verify", "version": 1, report, model, match, sha256, expected_sha256}.
nlohmann::ordered_json verify_json(const VerifyResult& result);

/// The one line that says why they do not belong together (result.match false).
std::string verify_mismatch_text(const VerifyResult& result);

}  // namespace kincal
