#include "kincal/cli/html_pages.hpp"

#include <cmath>
#include <vector>

#include "kincal/cli/html_report.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;
using L = Verdict::Level;

double number_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

std::string text_at(const Json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

std::string fmt(double v, int digits = 4) { return format_number(v, digits); }

}  // namespace

std::string render_validation_html(const Json& v) {
  std::vector<Verdict> verdicts;
  const std::string verdict = text_at(v, "verdict");
  const std::string stats = "standardized RMS " + fmt(number_at(v, "standardized_rms"), 3) +
                            " (1 = as predicted), P(larger) " + fmt(number_at(v, "p_larger"), 3);
  if (verdict == "not_tested")
    verdicts.push_back({L::kNote,
                        "Nothing predicts the residuals (no report, no reading_std): the errors "
                        "are shown, the consistency test is not made.",
                        "Give the calibration's report (--report) or state reading_std."});
  else if (verdict == "consistent")
    verdicts.push_back(
        {L::kGood, "The held-out residuals are what the calibration predicts: " + stats + ".", ""});
  else if (verdict == "larger_than_predicted")
    verdicts.push_back({L::kProblem,
                        "The held-out residuals are larger than predicted: " + stats +
                            ". The model misses something, or its uncertainty is understated.",
                        "Check the rows with the largest residuals, the fixed parameters "
                        "(kincal observability --sensitivity) and the stated reading_std."});
  else
    verdicts.push_back({L::kNote,
                        "The held-out residuals are smaller than predicted: " + stats +
                            ". The stated noise or uncertainty is pessimistic.",
                        ""});
  if (v.contains("position_error_mm") && v["position_error_mm"].is_object()) {
    const Json& p = v["position_error_mm"];
    const double after = p.contains("after") ? number_at(p["after"], "mean") : NAN;
    const double before =
        p.contains("before") && p["before"].is_object() ? number_at(p["before"], "mean") : NAN;
    if (std::isfinite(after) && std::isfinite(before))
      verdicts.push_back({after < before ? L::kGood : L::kProblem,
                          "Mean 3-D position error of the measured point: " + fmt(after, 4) +
                              " mm, against " + fmt(before, 4) + " mm before calibration.",
                          after < before ? ""
                                         : "The calibration made the machine less accurate "
                                           "on these data: check the data and the free "
                                           "parameters."});
    else if (std::isfinite(after))
      verdicts.push_back(
          {L::kNote, "Mean 3-D position error of the measured point: " + fmt(after, 4) + " mm.",
           "Give --report or --before to compare with the model before calibration."});
  }
  if (verdict != "not_tested" &&
      !(v.contains("parameter_uncertainty") && v["parameter_uncertainty"] == true))
    verdicts.push_back({L::kNote,
                        "The prediction is the noise alone: the parameters are taken as exact.",
                        "Give the calibration's report (--report) to include their uncertainty."});

  HtmlPage page("kincal validate: " + text_at(v, "model") + " on " + text_at(v, "data"));
  page.add_section("verdicts", "Verdicts", verdicts_html(verdicts));
  Json summary = Json::object();
  for (const char* key :
       {"model", "data", "report", "configurations", "readings", "noise", "standardized_rms",
        "chi_square", "degrees_of_freedom", "p_larger", "p_smaller", "significance", "verdict"})
    if (v.contains(key)) summary[key] = v[key];
  page.add_section("summary", "Summary", json_table_html(summary));
  if (v.contains("position_error_mm") && v["position_error_mm"].is_object()) {
    Json table = Json::array();
    for (const char* which : {"before", "after"}) {
      const Json& p = v["position_error_mm"];
      if (!p.contains(which) || !p[which].is_object()) continue;
      Json row = {{"model", which}};
      row.update(p[which]);
      table.push_back(row);
    }
    page.add_section("position", "3-D position error of the measured point (mm)",
                     json_table_html(table));
  }
  if (v.contains("per_reading"))
    page.add_section("readings", "Residuals per reading against the prediction",
                     json_table_html(v["per_reading"]));
  if (v.contains("residuals") && !v["residuals"].empty())
    page.add_section("residuals", "Residuals per configuration", json_table_html(v["residuals"]));
  return page.str();
}

std::string render_design_html(const Json& d) {
  const Json& predicted = d.contains("predicted_pose_error") ? d["predicted_pose_error"] : Json();
  auto rms = [&](const char* which) {
    return predicted.is_object() && predicted.contains(which)
               ? number_at(predicted[which], "position_rms_mm")
               : NAN;
  };
  const double designed = rms("designed"), random = rms("random"), nominal = rms("nominal");
  std::vector<Verdict> verdicts;
  if (std::isfinite(designed) && std::isfinite(random) && designed > 0)
    verdicts.push_back({designed < random ? L::kGood : L::kWarning,
                        "Predicted position error over the workspace: " + fmt(designed, 3) +
                            " mm RMS with this design, " + fmt(random, 3) +
                            " mm with random configurations of the same count (" +
                            fmt(random / designed, 3) + " times).",
                        ""});
  if (std::isfinite(designed) && std::isfinite(nominal))
    verdicts.push_back(
        designed < nominal
            ? Verdict{L::kGood,
                      "Calibrating from it is expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Measure the configurations of the template, fill in the readings, then "
                      "kincal calibrate."}
            : Verdict{L::kProblem,
                      "Even this design is not expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Add measurements (--count), a second sensor placement, or what you know "
                      "as prior_std."});
  if (d.contains("noise_std_assumed") && d["noise_std_assumed"] == true)
    verdicts.push_back({L::kWarning,
                        "The reading noise was assumed (the model states no reading_std): the "
                        "absolute predictions scale with it.",
                        "State reading_std in the model, or give --noise-std."});

  if (d.contains("exchange") && d["exchange"].contains("bound")) {
    const double ratio = number_at(d["exchange"]["bound"], "std_ratio");
    if (std::isfinite(ratio))
      verdicts.push_back({ratio < 1.05 ? L::kGood : L::kNote,
                          "No design of " +
                              (d.contains("count") && d["count"].is_number_integer()
                                   ? std::to_string(d["count"].get<long long>())
                                   : std::string("this size")) +
                              " from these candidates can do more than " +
                              fmt(100 * (ratio - 1), 3) +
                              " % better than this one (a certified bound on the criterion, "
                              "converted to standard deviations).",
                          ratio < 1.05 ? "" : "More exchange passes or candidates may help."});
  }

  HtmlPage page("kincal design: " + text_at(d, "model"));
  page.add_section("verdicts", "Verdicts", verdicts_html(verdicts));
  Json summary = Json::object();
  for (const char* key : {"model", "criterion", "criterion_meaning", "count", "configurations",
                          "seed", "prior", "existing_readings", "template"})
    if (d.contains(key)) summary[key] = d[key];
  page.add_section("summary", "Summary", json_table_html(summary));
  if (predicted.is_object()) {
    // One row per quantity, one column per design.
    Json rows = Json::array();
    if (predicted.contains("designed"))
      for (const auto& [quantity, value] : predicted["designed"].items()) {
        Json row = {{"quantity", quantity}};
        for (const char* which : {"designed", "random", "nominal"})
          row[which] = predicted.contains(which) && predicted[which].contains(quantity)
                           ? predicted[which][quantity]
                           : Json();
        rows.push_back(row);
      }
    page.add_section("prediction", "Predicted pose error", json_table_html(rows));
  }
  if (d.contains("parameters"))
    page.add_section("parameters", "Predicted parameter std", json_table_html(d["parameters"]));
  // One row per figure: the nested objects flattened ("exchange passes", "bound value").
  Json search = Json::object();
  if (d.contains("candidates"))
    for (const auto& [key, value] : d["candidates"].items()) search["candidates " + key] = value;
  if (d.contains("exchange"))
    for (const auto& [key, value] : d["exchange"].items()) {
      if (key != "bound") {
        search["exchange " + key] = value;
        continue;
      }
      for (const auto& [b, v] : value.items()) search["bound " + b] = v;
    }
  page.add_section("search", "Candidates and exchange", json_table_html(search));
  return page.str();
}

}  // namespace kincal::cli
