// The page of `kincal design --html` (cli/html_pages.hpp).

#include <algorithm>
#include <cmath>
#include <vector>

#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/html_pose_accuracy.hpp"
#include "kincal/cli/html_report.hpp"
#include "kincal/cli/html_values.hpp"
#include "kincal/cli/svg_plot.hpp"

namespace kincal::cli {

namespace {

using namespace html_values;
using L = Verdict::Level;

std::vector<Verdict> design_verdicts(const Json& d) {
  const Json& predicted = member(d, "predicted_pose_error");
  auto rms = [&](const char* which) {
    return number_at(member(predicted, which), "position_rms_mm");
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
                      "Add measurements (--poses), a second sensor placement, or what you know "
                      "as prior_std."});
  if (const auto target = target_verdict(member(d, "target"))) verdicts.push_back(*target);
  if (member(d, "noise_std_assumed") == true)
    verdicts.push_back({L::kWarning,
                        "The reading noise was assumed (the model states no reading_std): the "
                        "absolute predictions scale with it.",
                        "State reading_std in the model, or give --noise-std."});
  const double ratio = number_at(member(member(d, "exchange"), "bound"), "std_ratio");
  if (std::isfinite(ratio))
    verdicts.push_back(
        {ratio < 1.05 ? L::kGood : L::kNote,
         "No design of " +
             (member(d, "count").is_number_integer() ? std::to_string(d["count"].get<long long>())
                                                     : std::string("this size")) +
             " from these candidates can do more than " + fmt(100 * (ratio - 1), 3) +
             " % better than this one (a certified bound on the criterion, "
             "converted to standard deviations).",
         ratio < 1.05 ? "" : "More exchange passes or candidates may help."});
  if (member(d, "partial") == true)
    verdicts.push_back({L::kWarning,
                        "The run was interrupted (in the " + text_at(d, "stopped_in") +
                            "): this is the best design found so far.",
                        "Run it again to the end; a full run may do better."});
  return verdicts;
}

std::string summary_html(const Json& d) {
  std::string out = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    out += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
           "</td></tr>";
  };
  row("model", text_at(d, "model"));
  row("criterion", text_at(d, "criterion") + ": " + text_at(d, "criterion_meaning"));
  row("measurements", fmt(number_at(d, "count"), 9) + " in " +
                          fmt(number_at(d, "configurations"), 9) + " configurations");
  std::string noise;
  for (const auto& [name, value] : member(d, "noise_std").items())
    noise += (noise.empty() ? "" : ", ") + name + " " +
             fmt(value.is_number() ? value.get<double>() : NAN, 4);
  row("reading noise std",
      noise + " (each in its reading's unit; from " + text_at(d, "noise_std_source") + ")");
  row("prior", member(d, "prior") == true ? "the model's prior_std" : "none");
  row("existing readings", fmt(number_at(d, "existing_readings"), 9));
  row("seed", fmt(number_at(d, "seed"), 20));
  row("measurement template", text_at(d, "template"));
  return out + "</table>";
}

// The chosen configurations among the candidates, on the candidates' principal plane.
std::string configuration_map_html(const Json& d) {
  const Json& map = member(d, "configuration_map");
  const Json& candidates = member(map, "candidates");
  const Json& chosen = member(map, "chosen");
  if (!candidates.is_array() || !chosen.is_array() || candidates.empty())
    return "<p>No configuration map.</p>";
  double lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
  auto extend = [&](const Json& list) {
    for (const auto& p : list) {
      if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number()) continue;
      lo_x = std::min(lo_x, p[0].get<double>());
      hi_x = std::max(hi_x, p[0].get<double>());
      lo_y = std::min(lo_y, p[1].get<double>());
      hi_y = std::max(hi_y, p[1].get<double>());
    }
  };
  extend(candidates);
  extend(chosen);
  const double mx = 0.05 * (hi_x - lo_x) + 1e-9, my = 0.05 * (hi_y - lo_y) + 1e-9;
  const Json& explained = member(map, "explained");
  auto share = [&](std::size_t k) {
    return explained.is_array() && explained.size() > k && explained[k].is_number()
               ? " (" + fmt(100 * explained[k].get<double>(), 3) + " % of the spread)"
               : std::string();
  };
  SvgChart chart(1000, 460, "Chosen configurations among the candidates");
  chart.set_x({lo_x - mx, hi_x + mx, false, "principal direction 1" + share(0)});
  chart.set_y({lo_y - my, hi_y + my, false, "principal direction 2" + share(1)});
  chart.draw_axes();
  for (const auto& p : candidates)
    if (p.is_array() && p.size() >= 2 && p[0].is_number() && p[1].is_number())
      chart.point(p[0].get<double>(), p[1].get<double>(), 1.6, "s5");
  int index = 0;
  for (const auto& p : chosen) {
    ++index;
    if (p.is_array() && p.size() >= 2 && p[0].is_number() && p[1].is_number())
      chart.point(p[0].get<double>(), p[1].get<double>(), 4.2, "s3",
                  "measurement " + std::to_string(index) + " of the template");
  }
  chart.text_px(chart.left() + 6, chart.top() + 12,
                "\xE2\x97\x8F chosen (" + std::to_string(chosen.size()) + ")", "legend s3");
  chart.text_px(chart.left() + 120, chart.top() + 12,
                "\xE2\x97\x8F candidates (" + std::to_string(candidates.size()) + " of " +
                    fmt(number_at(map, "candidates_total"), 9) + " shown)",
                "legend s5");
  return chart.str() +
         "<p>The actuator values of every configuration, each scaled to its range over the "
         "candidates, projected on the plane that shows most of the candidates' spread (a plane "
         "cannot show every direction: chosen configurations that look central here may be "
         "extreme along the others).</p>";
}

// The criterion after the greedy start and after each exchange pass.
std::string progress_html(const Json& d) {
  const Json& exchange = member(d, "exchange");
  std::vector<double> values = {number_at(exchange, "greedy_value")};
  for (const auto& v : member(exchange, "pass_values"))
    values.push_back(v.is_number() ? v.get<double>() : NAN);
  const double random = number_at(exchange, "random_value");
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) return "<p>No criterion values to plot.</p>";
  if (std::isfinite(random)) lo = std::min(lo, random), hi = std::max(hi, random);
  const double pad = hi > lo ? 0.1 * (hi - lo) : std::max(1e-9, 0.1 * std::abs(hi));
  const std::string criterion = text_at(d, "criterion");
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
  return chart.str() + "<p>" + esc(text_at(d, "criterion_meaning")) + ". " +
         fmt(number_at(exchange, "passes"), 9) + " passes exchanged " +
         fmt(number_at(exchange, "exchanges"), 9) + " measurements.</p>";
}

std::string parameters_html(const Json& d) {
  std::string out =
      "<table><tr><th class=\"name\">parameter</th><th>unit</th><th>designed std</th>"
      "<th>random std</th><th>nominal std (assumed spread)</th></tr>";
  for (const auto& p : member(d, "parameters")) {
    const bool rad = text_at(p, "unit") == "rad";
    const double scale = rad ? 1000 : 1;
    out += "<tr><td class=\"name\">" + esc(text_at(p, "name")) + "</td><td>" +
           (rad ? std::string("mrad") : esc(text_at(p, "unit"))) + "</td><td>" +
           fmt(number_at(p, "designed_std") * scale, 3) + "</td><td>" +
           fmt(number_at(p, "random_std") * scale, 3) + "</td><td>" +
           fmt(number_at(p, "nominal_std") * scale, 3) + "</td></tr>";
  }
  return out + "</table>";
}

std::string search_html(const Json& d) {
  const Json& c = member(d, "candidates");
  const Json& e = member(d, "exchange");
  std::string out = "<table>";
  auto row = [&](const std::string& key, const std::string& value) {
    out += "<tr><th class=\"name\">" + esc(key) + "</th><td class=\"name\">" + esc(value) +
           "</td></tr>";
  };
  row("candidates", fmt(number_at(c, "total"), 9) + " reachable (" +
                        fmt(number_at(c, "corners"), 9) + " corners of the box + random draws)");
  row("rejected", fmt(number_at(c, "rejected_unreachable"), 9) + " unreachable, " +
                      fmt(number_at(c, "rejected_singular"), 9) + " below the singularity margin " +
                      fmt(number_at(c, "singularity_margin"), 3));
  row("criterion", "greedy start " + fmt(number_at(e, "greedy_value"), 6) +
                       ", after the exchange " + fmt(number_at(e, "value"), 6) +
                       ", random design " + fmt(number_at(e, "random_value"), 6));
  const Json& b = member(e, "bound");
  if (b.is_object())
    row("bound", "no design can pass " + fmt(number_at(b, "value"), 6) + " (relaxed optimum " +
                     fmt(number_at(b, "relaxed_value"), 6) + ", " +
                     fmt(number_at(b, "iterations"), 9) + " iterations)");
  return out + "</table>";
}

}  // namespace

std::string render_design_html(const Json& d) {
  HtmlPage page("kincal design: " + text_at(d, "model"));
  page.add_section("verdicts", "Verdicts", verdicts_html(design_verdicts(d)));
  page.add_section("summary", "Summary", summary_html(d));
  page.add_section("prediction", "Predicted pose error",
                   pose_accuracy_html(member(d, "predicted_pose_error"),
                                      {{"designed", "designed"},
                                       {"random", "random, same count"},
                                       {"nominal", "nominal model (assumed spread)"}},
                                      member(d, "target")));
  page.add_section("configurations", "Chosen configurations", configuration_map_html(d));
  page.add_section("progress", "Criterion over the exchange", progress_html(d));
  page.add_section("parameters", "Predicted parameter std", parameters_html(d));
  page.add_section("search", "Candidates and exchange", search_html(d));
  return page.str();
}

}  // namespace kincal::cli
