// The page of an experiment design (design_html, pages.hpp).

#include <algorithm>
#include <cmath>
#include <vector>

#include "kincal/framework/report/html_page.hpp"
#include "kincal/framework/report/pages.hpp"
#include "kincal/framework/report/sections.hpp"
#include "kincal/framework/workflows/design_map.hpp"

namespace kincal::report {

namespace {

using L = Finding::Level;

// The bound's ratio of standard deviations, NaN without a bound.
double bound_ratio(const ExperimentDesignResult& r) {
  return std::isfinite(r.bound.bound) ? finite_or_nan(r.std_ratio) : NAN;
}

std::vector<Finding> design_findings(const ExperimentDesignResult& r,
                                     const std::optional<TargetJudgement>& target) {
  const double designed = finite_or_nan(r.designed_pose.position_rms),
               random = finite_or_nan(r.random_pose.position_rms),
               nominal = finite_or_nan(r.nominal_pose.position_rms);
  std::vector<Finding> verdicts;
  if (std::isfinite(designed) && std::isfinite(random) && designed > 0)
    verdicts.push_back({"random", designed < random ? L::kGood : L::kWarning,
                        "Predicted position error over the workspace: " + fmt(designed, 3) +
                            " mm RMS with this design, " + fmt(random, 3) +
                            " mm with random configurations of the same count (" +
                            fmt(random / designed, 3) + " times).",
                        ""});
  if (std::isfinite(designed) && std::isfinite(nominal))
    verdicts.push_back(
        designed < nominal
            ? Finding{"accuracy", L::kGood,
                      "Calibrating from it is expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Measure the configurations of the template, fill in the readings, then "
                      "kincal calibrate."}
            : Finding{"accuracy", L::kDoNotLoad,
                      "Even this design is not expected to beat the nominal model (" +
                          fmt(nominal, 3) + " mm RMS).",
                      "Add measurements (--poses), a second sensor placement, or what you know "
                      "as prior_std."});
  if (target) verdicts.push_back(target_finding(*target));
  const double ratio = bound_ratio(r);
  if (std::isfinite(ratio))
    verdicts.push_back({"bound", ratio < 1.05 ? L::kGood : L::kNote,
                        "No design of " + std::to_string(r.options.count) +
                            " from these candidates can do more than " + fmt(100 * (ratio - 1), 3) +
                            " % better than this one (a certified bound on the criterion, "
                            "converted to standard deviations).",
                        ratio < 1.05 ? "" : "More exchange passes or candidates may help."});
  if (r.partial)
    verdicts.push_back({"partial", L::kWarning,
                        "The run was interrupted (in the " + r.stopped_in +
                            "): this is the best design found so far.",
                        "Run it again to the end; a full run may do better."});
  return verdicts;
}

std::string summary_html(const ExperimentDesignResult& r, const std::string& template_path) {
  const DesignOptions& design = r.options;
  std::string out = "<table>";
  out += summary_row("model", r.model_file);
  out +=
      summary_row("criterion", std::string(to_string(design.criterion)) + ": " +
                                   criterion_meaning(design.criterion, design.orientation_length));
  out += summary_row("measurements", fmt(design.count, 9) + " in " +
                                         fmt(static_cast<double>(r.rows.size()), 9) +
                                         " configurations");
  std::string noise;
  for (int i = 0; i < r.model->num_readings(); ++i)
    noise += (noise.empty() ? "" : ", ") + r.model->reading_names()[i] + " " +
             fmt(r.setup.noise_std[i], 4);
  const std::string source =
      r.noise_source == "the model's reading_std" ? "reading_std" : r.noise_source;
  out += summary_row("reading noise std",
                     noise + " (each in its reading's unit; from " + source + ")");
  out += summary_row("prior", r.setup.has_prior ? "the model's prior_std" : "none");
  out += summary_row("existing readings", fmt(r.setup.existing_readings, 9));
  out += summary_row("seed", fmt(static_cast<double>(design.seed), 20));
  out += summary_row("measurement template", template_path);
  return out + "</table>";
}

// The chosen configurations among the candidates, on the candidates' principal plane.
std::string configuration_map_html(const ExperimentDesignResult& r) {
  const DesignMap map = design_configuration_map(r.candidates, r.design.chosen);
  if (!map.computed || map.candidates.empty()) return "<p>No configuration map.</p>";
  double lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
  auto extend = [&](const std::vector<std::array<double, 2>>& list) {
    for (const auto& p : list) {
      lo_x = std::min(lo_x, p[0]);
      hi_x = std::max(hi_x, p[0]);
      lo_y = std::min(lo_y, p[1]);
      hi_y = std::max(hi_y, p[1]);
    }
  };
  extend(map.candidates);
  extend(map.chosen);
  const double mx = 0.05 * (hi_x - lo_x) + 1e-9, my = 0.05 * (hi_y - lo_y) + 1e-9;
  auto share = [&](std::size_t k) {
    return " (" + fmt(100 * map.explained[k], 3) + " % of the spread)";
  };
  SvgChart chart(1000, 460, "Chosen configurations among the candidates");
  chart.set_x({lo_x - mx, hi_x + mx, false, "principal direction 1" + share(0)});
  chart.set_y({lo_y - my, hi_y + my, false, "principal direction 2" + share(1)});
  chart.draw_axes();
  for (const auto& p : map.candidates) chart.point(p[0], p[1], 1.6, "s5");
  int index = 0;
  for (const auto& p : map.chosen) {
    ++index;
    chart.point(p[0], p[1], 4.2, "s3", "measurement " + std::to_string(index) + " of the template");
  }
  chart.text_px(chart.left() + 6, chart.top() + 12,
                "\xE2\x97\x8F chosen (" + std::to_string(map.chosen.size()) + ")", "legend s3");
  chart.text_px(chart.left() + 120, chart.top() + 12,
                "\xE2\x97\x8F candidates (" + std::to_string(map.candidates.size()) + " of " +
                    fmt(static_cast<double>(map.candidates_total), 9) + " shown)",
                "legend s5");
  return chart.str() +
         "<p>The actuator values of every configuration, each scaled to its range over the "
         "candidates, projected on the plane that shows most of the candidates' spread (a plane "
         "cannot show every direction: chosen configurations that look central here may be "
         "extreme along the others).</p>";
}

// The criterion of the random design of the same count, compared with.
double random_value(const ExperimentDesignResult& r) {
  return finite_or_nan(criterion_value(
      r.options.criterion, design_information(r.candidates, r.random, r.setup), r.setup));
}

// The criterion after the greedy start and after each exchange pass.
std::string progress_html(const ExperimentDesignResult& r, double random) {
  const DesignResult& exchange = r.design;
  std::vector<double> values = {finite_or_nan(exchange.greedy_value)};
  for (double v : exchange.pass_values) values.push_back(v);
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) return "<p>No criterion values to plot.</p>";
  if (std::isfinite(random)) lo = std::min(lo, random), hi = std::max(hi, random);
  const double pad = hi > lo ? 0.1 * (hi - lo) : std::max(1e-9, 0.1 * std::abs(hi));
  const std::string criterion = to_string(r.options.criterion);
  SvgChart chart(1000, 300, "Criterion " + criterion + " over the exchange passes");
  chart.set_x({-0.5, values.size() - 0.5, false, "pass (0: the greedy start)"});
  chart.set_y({lo - pad, hi + pad, false, "criterion " + criterion});
  chart.draw_axes();
  std::vector<std::pair<double, double>> line;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) line.push_back({static_cast<double>(i), values[i]});
  chart.polyline(line, "curve");
  for (const auto& [x, y] : line)
    chart.point(
        x, y, 3.5, "s0",
        (x == 0 ? std::string("greedy start") : "after pass " + fmt(x, 3)) + ": " + fmt(y, 6));
  if (std::isfinite(random)) {
    chart.line(-0.5, random, values.size() - 0.5, random, "threshold");
    chart.text(values.size() - 0.6, random, "random design of the same count", "legend", "end");
  }
  return chart.str() + "<p>" +
         esc(criterion_meaning(r.options.criterion, r.options.orientation_length)) + ". " +
         fmt(exchange.passes, 9) + " passes exchanged " + fmt(exchange.exchanges, 9) +
         " measurements.</p>";
}

std::string parameters_html(const ExperimentDesignResult& r) {
  std::string out =
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>designed std</th>"
      "<th>random std</th><th>nominal std (assumed spread)</th></tr>";
  for (std::size_t c = 0; c < r.setup.free_indices.size(); ++c) {
    const Parameter& p = r.model->parameters()[r.setup.free_indices[c]];
    const auto k = static_cast<Eigen::Index>(c);
    const bool rad = p.unit == "rad";
    const double scale = rad ? 1000 : 1;
    out += "<tr><td class=\"name\">" + esc(p.name) + "</td><td>" +
           (rad ? std::string("mrad") : esc(p.unit)) + "</td><td>" +
           fmt(finite_or_nan(std::sqrt(r.designed_cov(k, k))) * scale, 3) + "</td><td>" +
           fmt(finite_or_nan(std::sqrt(r.random_cov(k, k))) * scale, 3) + "</td><td>" +
           fmt(r.setup.scale[k] * scale, 3) + "</td></tr>";
  }
  return out + "</table>";
}

std::string search_html(const ExperimentDesignResult& r, double random) {
  const DesignCandidates& c = r.candidates;
  const DesignResult& e = r.design;
  std::string out = "<table>";
  out +=
      summary_row("candidates", fmt(static_cast<double>(c.size()), 9) + " reachable (" +
                                    fmt(c.num_corners, 9) + " corners of the box + random draws)");
  out += summary_row(
      "rejected",
      fmt(c.rejected_unreachable, 9) + " unreachable, " + fmt(c.rejected_singular, 9) +
          " below the singularity margin " + fmt(r.options.min_singularity_margin, 3) +
          (c.rejected_unseen ? ", " + fmt(c.rejected_unseen, 9) + " with nothing in view"
                             : std::string()));
  out += summary_row("criterion", "greedy start " + fmt(finite_or_nan(e.greedy_value), 6) +
                                      ", after the exchange " +
                                      fmt(finite_or_nan(e.criterion_value), 6) +
                                      ", random design " + fmt(random, 6));
  const DesignBound& b = r.bound;
  if (std::isfinite(b.bound))
    out += summary_row("bound", "no design can pass " + fmt(finite_or_nan(b.bound), 6) +
                                    " (relaxed optimum " + fmt(finite_or_nan(b.relaxed_value), 6) +
                                    ", " + fmt(b.iterations, 9) + " iterations)");
  return out + "</table>";
}

}  // namespace

std::string design_html(const ExperimentDesignResult& r, const std::string& template_path,
                        const std::optional<TargetJudgement>& target) {
  const double random = random_value(r);
  HtmlPage page("kincal design: " + r.model_file);
  page.add_section("verdicts", "Verdicts", findings_html(design_findings(r, target)));
  page.add_section("summary", "Summary", summary_html(r, template_path));
  page.add_section("prediction", "Predicted pose error",
                   pose_accuracy_html(r.designed_pose.samples,
                                      {{"designed", &r.designed_pose},
                                       {"random, same count", &r.random_pose},
                                       {"nominal model (assumed spread)", &r.nominal_pose}},
                                      target ? &*target : nullptr));
  page.add_section("configurations", "Chosen configurations", configuration_map_html(r));
  page.add_section("progress", "Criterion over the exchange", progress_html(r, random));
  page.add_section("parameters", "Predicted parameter std", parameters_html(r));
  page.add_section("search", "Candidates and exchange", search_html(r, random));
  return page.str();
}

}  // namespace kincal::report
