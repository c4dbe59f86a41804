#include "kincal/framework/workflows/report_prediction.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kincal/framework/io/json_input.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

double report_number(const Json& value, const std::string& where) {
  if (!value.is_number()) throw std::invalid_argument(where + ": expected a number");
  return value.get<double>();
}

// A report's number must be one validate can compute with: its square a finite, normal
// double (so 5e-324 and 1e300 are refused as a noise or a std), within [low, high].
double report_number_in(const Json& value, const std::string& where, double low, double high,
                        const char* expected) {
  const double v = report_number(value, where);
  if (!(v >= low && v <= high)) {
    char text[40];
    std::snprintf(text, sizeof text, "%.6g", v);
    throw std::invalid_argument(where + " is " + text + "; expected " + expected);
  }
  return v;
}
constexpr double kLargest = 1e150, kSmallest = 1e-150;

}  // namespace

ReportPrediction read_report_prediction(const std::string& path) {
  // A calibration report lists every residual: about 90 bytes per configuration, so 16 MiB
  // (the limit for files a user writes) is passed from about 10^5 configurations on. The
  // limit still stops a device or a runaway file.
  JsonLimits limits;
  limits.max_bytes = kMaxCalibrationReportBytes;
  return parse_report_prediction(read_json_file(path, "calibration report", limits), path);
}

ReportPrediction parse_report_prediction(const nlohmann::ordered_json& report,
                                         const std::string& path) {
  if (!report.is_object() || report.value("format", "") != "kincal-calibration-report")
    throw std::invalid_argument(
        path + ": expected a calibration report (format \"kincal-calibration-report\")");
  ReportPrediction p;
  for (const char* key : {"sigma_hat", "weighted", "parameters", "correlation"})
    if (!report.contains(key)) throw std::invalid_argument(path + ": no '" + key + "' field");
  if (!report["sigma_hat"].is_null()) {
    p.sigma_hat = report_number(report["sigma_hat"], path + ": sigma_hat");
    if (p.sigma_hat != 0)  // 0 (an exact fit) is refused with its reason by the caller
      report_number_in(report["sigma_hat"], path + ": sigma_hat", kSmallest, kLargest,
                       "a finite noise >= 1e-150 and <= 1e150");
  }
  if (!report["weighted"].is_boolean())
    throw std::invalid_argument(path + ": weighted: expected true or false");
  p.weighted = report["weighted"].get<bool>();
  p.sigma_unit = report.value("sigma_hat_unit", "");
  const Json& parameters = report["parameters"];
  if (!parameters.is_array()) throw std::invalid_argument(path + ": parameters: expected an array");
  const int n = static_cast<int>(parameters.size());
  p.std.resize(n);
  p.nominal = VectorXd::Constant(n, NAN);
  for (int i = 0; i < n; ++i) {
    const Json& entry = parameters[i];
    const std::string where = path + ": parameters[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("name") || !entry["name"].is_string() ||
        !entry.contains("std"))
      throw std::invalid_argument(where + ": expected {\"name\": ..., \"std\": ...}");
    p.names.push_back(entry["name"].get<std::string>());
    if (entry.contains("nominal") && entry["nominal"].is_number())
      p.nominal[i] = entry["nominal"].get<double>();
    if (entry["std"].is_null())
      throw std::invalid_argument(where +
                                  ": std is null (the calibration could not estimate it); "
                                  "validate without --report to compare with the noise alone");
    p.std[i] = report_number_in(entry["std"], where + ".std", 0, kLargest,
                                "a finite std >= 0 and <= 1e150");
  }
  const Json& correlation = report["correlation"];
  if (!correlation.is_array() || static_cast<int>(correlation.size()) != n)
    throw std::invalid_argument(path + ": correlation: expected " + std::to_string(n) + " x " +
                                std::to_string(n) + " numbers");
  p.correlation.resize(n, n);
  for (int i = 0; i < n; ++i) {
    if (!correlation[i].is_array() || static_cast<int>(correlation[i].size()) != n)
      throw std::invalid_argument(path + ": correlation[" + std::to_string(i) + "]: expected " +
                                  std::to_string(n) + " numbers");
    for (int j = 0; j < n; ++j)
      p.correlation(i, j) = report_number_in(
          correlation[i][j],
          path + ": correlation[" + std::to_string(i) + "][" + std::to_string(j) + "]", -1 - 1e-9,
          1 + 1e-9, "a correlation in [-1, 1]");
  }
  if (report.contains("calibrated_model") && !report["calibrated_model"].is_null()) {
    const Json& entry = report["calibrated_model"];
    if (!entry.is_object() || !entry.contains("sha256") || !entry["sha256"].is_string())
      throw std::invalid_argument(
          path + ": calibrated_model: expected {\"file\": ..., \"sha256\": ...} or null");
    p.calibrated_sha256 = entry["sha256"].get<std::string>();
  }
  return p;
}

ValidationPrediction prediction_from_report(const ReportPrediction& report,
                                            const MeasurementModel& model,
                                            const std::string& report_file,
                                            const std::string& model_file) {
  ValidationPrediction p;
  if (!(report.sigma_hat > 0))
    throw std::invalid_argument(
        report_file +
        ": sigma_hat is null or 0 (an exact fit says nothing about the noise); "
        "expected a calibration with more readings than parameters");
  if (report.weighted != model.weighted())
    throw std::invalid_argument(report_file + ": weighted is " +
                                (report.weighted ? "true" : "false") + " but " + model_file +
                                (model.weighted() ? " states" : " states no") +
                                " reading_std; expected the model the report was written for");
  if (!report.weighted && report.sigma_unit == "mixed")
    throw std::invalid_argument(
        report_file +
        ": sigma_hat pools mm and rad (no reading_std); state reading_std in the "
        "model and calibrate again");
  // Weighted: sigma_hat is the ratio of the scatter to the stated std; otherwise it is the
  // std itself, in the readings' one unit.
  p.noise_std = report.weighted
                    ? VectorXd(report.sigma_hat * model.reading_std())
                    : VectorXd(VectorXd::Constant(model.num_readings(), report.sigma_hat));
  p.noise_source = report.weighted ? "sigma_hat x reading_std" : "sigma_hat";
  for (const auto& name : report.names) {
    const int index = model.parameters().find(name);
    if (index < 0)
      throw std::invalid_argument(report_file + ": parameter '" + name + "' is not in " +
                                  model_file + "; expected the model the report was written for");
    p.parameters.push_back(index);
  }
  p.covariance = report.std.asDiagonal() * report.correlation * report.std.asDiagonal();
  return p;
}

ValidationPrediction prediction_from_calibration(const CalibrationReport& report,
                                                 const MeasurementModel& model) {
  ReportPrediction r;
  r.sigma_hat = report.uncertainty.sigma;
  r.weighted = report.weighted;
  r.sigma_unit = sigma_unit(report);
  r.names = report.names;
  r.std = report.uncertainty.std;
  r.correlation = report.uncertainty.correlation;
  if (r.std.size() != static_cast<Eigen::Index>(r.names.size()) || !r.std.allFinite())
    throw std::invalid_argument(
        "the calibration could not estimate every parameter's std; validate without its "
        "prediction to compare with the noise alone");
  return prediction_from_report(r, model, "the calibration", "the model");
}

std::optional<VectorXd> values_before_calibration(const ReportPrediction& report,
                                                  const ValidationPrediction& prediction,
                                                  const VectorXd& values) {
  if (!report.nominal.allFinite()) return std::nullopt;
  VectorXd v = values;
  for (std::size_t i = 0; i < report.names.size(); ++i)
    v[prediction.parameters[i]] = report.nominal[static_cast<int>(i)];
  return v;
}

}  // namespace kincal
