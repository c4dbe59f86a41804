#include "kincal/framework/workflows/design.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <stdexcept>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/workflows/design_map.hpp"
#include "kincal/framework/workflows/option_name.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

// An option as the face spells it: "--poses" for the program, "poses" for Python.
std::string option(const ExperimentDesignRequest& request, const std::string& name) {
  return option_name(request.option_prefix, name);
}

// The information matrix M (normalised parameters) must determine every free parameter:
// finite, and of full numerical rank, with its square root's columns scaled as calibrate
// scales the Jacobian's. Throws std::invalid_argument "<what>: <the deficiency>; <remedy>"
// otherwise.
void check_information(const MatrixXd& M, const std::vector<std::string>& names,
                       const std::string& what, const std::string& remedy) {
  const int n = static_cast<int>(M.rows());
  if (!M.allFinite())
    throw std::invalid_argument(
        what +
        ": the information matrix is not finite; expected a reading noise std "
        "(--noise-std, the model's reading_std) on the scale of the readings");
  // R with R^T R = M: zero columns for the parameters nothing informs (exactly, so that
  // they are named), the symmetric square root of the rest.
  std::vector<int> seen;
  for (int i = 0; i < n; ++i)
    if (M(i, i) > 0) seen.push_back(i);
  const int n_seen = static_cast<int>(seen.size());
  MatrixXd R = MatrixXd::Zero(std::max(n_seen, 1), n);
  if (n_seen > 0) {
    MatrixXd sub(n_seen, n_seen);
    for (int a = 0; a < n_seen; ++a)
      for (int b = 0; b < n_seen; ++b) sub(a, b) = M(seen[a], seen[b]);
    const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(sub);
    const MatrixXd root =
        eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
    for (int a = 0; a < n_seen; ++a) R.col(seen[a]) = root.col(a);
  }
  const Identifiability a = analyze_identifiability(R, names);
  if (a.rank_deficient())
    throw std::invalid_argument(what + ": " + describe_deficiency(a) + "; " + remedy);
}

// The template: header, comments saying what to fill in, one row per configuration with the
// actuator values and empty reading fields.
std::string template_csv(const MeasurementModel& model, const Measurements& rows,
                         const std::string& heading) {
  std::ostringstream out;
  out << heading;
  const auto actuators = model.mechanism().actuator_names();
  const auto readings = model.reading_names();
  const bool several = model.sensors().size() > 1;
  std::string header;
  for (const auto& n : actuators) header += (header.empty() ? "" : ",") + n;
  for (const auto& n : readings) header += "," + n;
  out << header << "\n";
  char buf[40];
  for (int r = 0; r < rows.size(); ++r) {
    if (several) {
      out << "# read:";
      for (std::size_t s = 0; s < model.sensors().size(); ++s)
        if (!std::isnan(rows.readings(r, model.sensor_reading_offset(static_cast<int>(s)))))
          out << " " << model.sensors()[s]->name();
      out << "\n";
    }
    for (int a = 0; a < rows.actuators.cols(); ++a) {
      std::snprintf(buf, sizeof buf, "%.17g", rows.actuators(r, a));
      out << (a ? "," : "") << buf;
    }
    for (int k = 0; k < rows.readings.cols(); ++k) out << ",";
    out << "\n";
  }
  return out.str();
}

// A figure, or "n/a" where it is not a number (the random design compared with may not
// determine every parameter).
std::string figure(double v) {
  char text[32];
  if (std::isfinite(v))
    std::snprintf(text, sizeof text, "%12.4g", v);
  else
    std::snprintf(text, sizeof text, "%12s", "n/a");
  return text;
}

std::string prediction_row(const char* label, double designed, double random, double nominal) {
  return format_text("  %-34s %s %s %s\n", label, figure(designed).c_str(), figure(random).c_str(),
                     figure(nominal).c_str());
}

}  // namespace

std::string criterion_meaning(DesignCriterion c, double orientation_length) {
  if (c == DesignCriterion::kI && orientation_length > 0) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "mean predicted pose variance |dp|^2 + (%g mm x dtheta)^2 over the workspace "
                  "(mm^2), minimised",
                  orientation_length);
    return buf;
  }
  switch (c) {
    case DesignCriterion::kD:
      return "log det of the information matrix, maximised";
    case DesignCriterion::kA:
      return "mean parameter variance / nominal spread^2, minimised";
    case DesignCriterion::kE:
      return "smallest eigenvalue of the information matrix, maximised";
    case DesignCriterion::kI:
      return "mean predicted position variance over the workspace (mm^2), minimised";
  }
  return "";
}

ExperimentDesignResult design_experiment(const ExperimentDesignRequest& request) {
  if (!request.model) throw std::invalid_argument("design: the request has no model");
  const MeasurementModel& model = *request.model;
  ExperimentDesignResult r;
  r.model = request.model;
  r.model_file = request.model_file;
  r.noise_source = request.noise_source;
  const auto say = [&](const std::string& text) {
    r.notes.push_back(text);
    if (request.on_note) request.on_note(text);
  };
  DesignOptions& design = r.options;
  design = request.options;
  if (design.count < 1)
    throw std::invalid_argument(option(request, "poses") + " must be at least 1");
  if (design.num_random < 0)
    throw std::invalid_argument(option(request, "candidates") + " must be >= 0");
  const int n = model.parameters().num_free();
  if (n == 0)
    throw std::invalid_argument("no free parameters: nothing to design for (use " +
                                option(request, "free") + ")");
  // A design weighs the readings against each other and against the prior by their noise,
  // and its predictions scale with it: no value is a safe guess.
  if (request.noise_std.size() == 0 && !model.weighted())
    throw std::invalid_argument(
        (request.model_file.empty() ? std::string("the model") : printable(request.model_file)) +
        " states no reading_std: give the readings' noise std, e.g. " +
        option(request, "noise-std") + " 0.0072mm (or reading_std in the model file)");
  design.noise_std = request.noise_std.size() ? request.noise_std : model.reading_std();
  // The stage a stop came in, for the report and the template.
  const DesignMonitor outer = request.options.monitor;
  if (outer)
    design.monitor = [&r, outer](const DesignStep& step) {
      if (outer(step)) return true;
      if (r.stopped_in.empty())
        r.stopped_in = step.pass ? std::string(step.stage) + " pass " + std::to_string(step.pass)
                                 : std::string(step.stage);
      return false;
    };
  DesignSetup& setup = r.setup;
  setup = make_design_setup(model, design, request.existing ? &*request.existing : nullptr);
  DesignCandidates& candidates = r.candidates;
  candidates = make_design_candidates(model, setup, design);
  if (candidates.stopped && candidates.size() < design.count) {
    r.stopped_before_design = true;
    return r;
  }
  if (candidates.size() < design.count)
    throw std::invalid_argument(
        "only " + std::to_string(candidates.size()) + " reachable candidates (" +
        std::to_string(candidates.rejected_unreachable) + " unreachable, " +
        std::to_string(candidates.rejected_singular) + " near-singular" +
        (candidates.rejected_unseen
             ? ", " + std::to_string(candidates.rejected_unseen) + " with nothing in view"
             : std::string()) +
        ") for " + option(request, "poses") + " " + std::to_string(design.count) + "; raise " +
        option(request, "candidates") + " or lower " + option(request, "singularity-margin"));
  if (request.when_rank_deficient == WhenRankDeficient::kFixDependent) {
    // What all the candidates together determine, preferred as calibrate prefers (the
    // mechanism's identification priority): design for those, the others fixed.
    const MatrixXd base = setup.base_information;
    MatrixXd J(base.rows() + candidates.rows.rows(), n);
    Eigen::SelfAdjointEigenSolver<MatrixXd> eig(base);
    J.topRows(base.rows()) =
        eig.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
    J.bottomRows(candidates.rows.rows()) = candidates.rows;
    std::vector<int> priority;
    const std::vector<int> all = model.identification_priority();
    for (int i : setup.free_indices)
      priority.push_back(all.empty() ? 0 : all[static_cast<std::size_t>(i)]);
    const std::vector<int> keep = identifiable_subset(J, priority);
    if (static_cast<int>(keep.size()) < n && !keep.empty()) {
      auto reduced = std::make_shared<MeasurementModel>(model);
      std::vector<std::string> fixed;
      for (int c = 0; c < n; ++c)
        if (std::find(keep.begin(), keep.end(), c) == keep.end()) {
          fixed.push_back(model.parameters()[setup.free_indices[static_cast<std::size_t>(c)]].name);
          reduced->parameters().set_free(fixed.back(), false);
        }
      ExperimentDesignRequest again = request;
      again.model = reduced;
      again.when_rank_deficient = WhenRankDeficient::kStop;
      std::string text = "the candidates determine " + std::to_string(keep.size()) + " of the " +
                         std::to_string(n) +
                         " free parameters: designing for those, the others fixed at their "
                         "model values (as calibrate keeps what its data determine):";
      for (const std::string& name : fixed) text += " " + name;
      say(text);
      ExperimentDesignResult out = design_experiment(again);
      out.notes.insert(out.notes.begin(), r.notes.begin(), r.notes.end());
      out.fixed_for_design = fixed;
      return out;
    }
  }
  const long long new_readings = [&] {
    long long k = 0;
    for (const auto& s : model.sensors()) k = std::max<long long>(k, s->num_readings());
    return k * design.count;
  }();
  if (!setup.has_prior && setup.existing_readings + new_readings < n)
    throw std::invalid_argument(
        option(request, "poses") + " " + std::to_string(design.count) + " gives at most " +
        std::to_string(new_readings + setup.existing_readings) + " readings for " +
        std::to_string(n) +
        " free parameters; expected at least as many readings as free parameters");
  for (int i : setup.free_indices) r.free_names.push_back(model.parameters()[i].name);
  // No design from these candidates can determine more than all of them together: a
  // parameter no reading sees, or a box of 0 (every candidate at home), is an error here,
  // not a template of copies of home with a criterion of -inf.
  check_information(
      setup.base_information + candidates.rows.transpose() * candidates.rows, r.free_names,
      "no design of these " + std::to_string(candidates.size()) +
          " candidates determines every free parameter",
      "widen the box (" + option(request, "config-range") + "), fix the parameters (" +
          option(request, "fix") + ") or state a prior (" + option(request, "prior-std") + ")");
  DesignResult& result = r.design;
  result = choose_design(candidates, setup, design);
  check_information(design_information(candidates, result.chosen, setup), r.free_names,
                    "the " + std::to_string(design.count) +
                        " measurements chosen do not determine every free parameter",
                    "raise " + option(request, "poses") + ", widen the box (" +
                        option(request, "config-range") + ") or state a prior (" +
                        option(request, "prior-std") + ")");
  if (!std::isfinite(result.criterion_value))
    throw std::invalid_argument(
        "the design's criterion " + std::string(to_string(design.criterion)) + " is " +
        (std::isnan(result.criterion_value) ? "not a number"
                                            : std::to_string(result.criterion_value)) +
        "; expected a finite value (a reading noise std on the scale of the readings, a box the "
        "readings see)");
  if (request.bound && design.criterion == DesignCriterion::kE)
    say(option(request, "bound") + ": the E criterion is not smooth; no bound is computed for it");
  r.bound = request.bound && !result.stopped && !candidates.stopped
                ? design_bound(candidates, setup, design, result.chosen)
                : DesignBound{};
  r.partial = candidates.stopped || result.stopped || r.bound.stopped;
  r.std_ratio = design_std_ratio_to_bound(design.criterion, result.criterion_value, r.bound, n);
  r.rows = design_rows(model, candidates, result.chosen);
  r.random = random_design(candidates, design.count, design.seed);
  r.designed_cov = design_covariance(design_information(candidates, result.chosen, setup), setup);
  r.random_cov = design_covariance(design_information(candidates, r.random, setup), setup);
  if (!r.random_cov.allFinite())
    say("the random design compared with does not determine every free parameter: its "
        "predictions are n/a (null in the JSON)");
  const MatrixXd nominal_cov = setup.scale.array().square().matrix().asDiagonal();
  r.designed_pose = predict_pose_errors(setup.workspace, r.designed_cov);
  r.random_pose = predict_pose_errors(setup.workspace, r.random_cov);
  r.nominal_pose = predict_pose_errors(setup.workspace, nominal_cov);
  return r;
}

std::string design_text(const ExperimentDesignResult& r, const std::string& template_path) {
  const DesignOptions& design = r.options;
  const DesignCandidates& candidates = r.candidates;
  const DesignResult& result = r.design;
  const DesignBound& bound = r.bound;
  const DesignSetup& setup = r.setup;
  const MeasurementModel& model = *r.model;
  const char* criterion = to_string(design.criterion);
  std::string noise_text;
  {
    const auto names = model.reading_names();
    const auto units = model.reading_units();
    std::set<std::string> seen;
    for (int i = 0; i < model.num_readings(); ++i) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %g %s", noise_text.empty() ? "" : ", ", names[i].c_str(),
                    setup.noise_std[i], units[i].c_str());
      if (seen.insert(names[i]).second && noise_text.size() < 150) noise_text += buf;
    }
    noise_text = noise_text.substr(0, 199);
  }
  std::string out;
  out += format_text(
      "kincal design: %s, criterion %s, %d measurements in %d configurations, seed %llu\n",
      printable(r.model_file).c_str(), criterion, design.count, r.rows.size(),
      static_cast<unsigned long long>(design.seed));
  out += format_text(
      "candidates: %d (%s; %d box corners + random; rejected: %d unreachable, %d below the "
      "singularity margin %g%s)\n",
      candidates.size(), ("from " + candidates.region).c_str(), candidates.num_corners,
      candidates.rejected_unreachable, candidates.rejected_singular, design.min_singularity_margin,
      model.sensors_can_miss()
          ? format_text(", %d with nothing in view", candidates.rejected_unseen).c_str()
          : "");
  out += format_text("exchange: %d passes, %d exchanges; criterion %s: greedy %.6g -> %.6g\n",
                     result.passes, result.exchanges, criterion, result.greedy_value,
                     result.criterion_value);
  if (std::isfinite(bound.bound))
    out += format_text(
        "bound: no design of %d from these candidates has criterion %s %s %.6g (certified "
        "after %d iterations); this design's %s are within %.2f %% of the best possible\n",
        design.count, criterion, design.criterion == DesignCriterion::kD ? "above" : "below",
        bound.bound, bound.iterations,
        design.criterion == DesignCriterion::kD   ? "parameter stds (geometric mean)"
        : design.criterion == DesignCriterion::kI ? "predicted position errors (RMS)"
                                                  : "parameter stds (RMS, relative)",
        100 * (r.std_ratio - 1));
  out += format_text(
      "prediction (linearised at the nominal values; reading noise std %s from %s%s%s):\n",
      noise_text.c_str(), r.noise_source.c_str(), setup.has_prior ? "; with the model's prior" : "",
      setup.existing_readings
          ? ("; with " + std::to_string(setup.existing_readings) + " existing readings").c_str()
          : "");
  out += format_text("  %-34s %12s %12s %12s\n", "", "designed", "random", "nominal");
  const PoseErrorPrediction &d = r.designed_pose, &a = r.random_pose, &o = r.nominal_pose;
  out += prediction_row("position error RMS (mm)", d.position_rms, a.position_rms, o.position_rms);
  out += prediction_row("position error mean 1sigma (mm)", d.position_mean_1sigma,
                        a.position_mean_1sigma, o.position_mean_1sigma);
  out += prediction_row("position error max 95% (mm)", d.position_max_95, a.position_max_95,
                        o.position_max_95);
  out += prediction_row("orientation error RMS (rad)", d.orientation_rms, a.orientation_rms,
                        o.orientation_rms);
  out += prediction_row("orientation error max 95% (rad)", d.orientation_max_95,
                        a.orientation_max_95, o.orientation_max_95);
  int name_width = 22;  // as wide as the longest name (an imported arm's reach 29)
  for (int index : setup.free_indices)
    name_width = std::max(name_width, static_cast<int>(std::min<std::size_t>(
                                          model.parameters()[index].name.size(), 128)));
  out += format_text("predicted parameter std:\n  %-*s %-4s %12s %12s %12s\n", name_width, "name",
                     "unit", "designed", "random", "nominal");
  for (std::size_t c = 0; c < setup.free_indices.size(); ++c) {
    const Parameter& p = model.parameters()[setup.free_indices[c]];
    const auto k = static_cast<Eigen::Index>(c);
    out +=
        format_text("  %-*s %-4s %s %s %s\n", name_width, p.name.c_str(), p.unit.c_str(),
                    figure(std::sqrt(r.designed_cov(k, k))).c_str(),
                    figure(std::sqrt(r.random_cov(k, k))).c_str(), figure(setup.scale[k]).c_str());
  }
  out += format_text("template: %s (%d configurations; fill in the reading columns)\n",
                     template_path.c_str(), r.rows.size());
  if (r.partial)
    out += format_text("PARTIAL: interrupted in the %s; the design is the best found so far\n",
                       r.stopped_in.c_str());
  return out;
}

nlohmann::ordered_json design_json(const ExperimentDesignResult& r,
                                   const std::string& template_path, const Json& target) {
  const DesignOptions& design = r.options;
  const DesignCandidates& candidates = r.candidates;
  const DesignResult& result = r.design;
  const DesignBound& bound = r.bound;
  const DesignSetup& setup = r.setup;
  const MeasurementModel& model = *r.model;
  Json j;
  j["format"] = "kincal-design";
  j["version"] = 1;
  j["model"] = r.model_file;
  j["criterion"] = to_string(design.criterion);
  j["criterion_meaning"] = criterion_meaning(design.criterion, design.orientation_length);
  if (design.criterion == DesignCriterion::kI)
    j["orientation_length_mm"] = design.orientation_length;
  j["count"] = design.count;
  j["configurations"] = r.rows.size();
  j["seed"] = design.seed;
  j["candidates"] = {{"total", candidates.size()},
                     {"corners", candidates.num_corners},
                     {"rejected_unreachable", candidates.rejected_unreachable},
                     {"rejected_singular", candidates.rejected_singular},
                     {"rejected_unseen", candidates.rejected_unseen},
                     {"singularity_margin", design.min_singularity_margin},
                     {"region", candidates.region}};
  if (candidates.region_low.size() > 0) {
    Json low = Json::object(), high = Json::object();
    for (int a = 0; a < model.mechanism().num_actuators(); ++a) {
      const Actuator& actuator = model.mechanism().actuators()[static_cast<std::size_t>(a)];
      low[actuator.name] = candidates.region_low[a];
      high[actuator.name] = candidates.region_high[a];
    }
    j["candidates"]["region_low"] = low;
    j["candidates"]["region_high"] = high;
  }
  Json noise = Json::object();
  for (int i = 0; i < model.num_readings(); ++i)
    noise[model.reading_names()[i]] = setup.noise_std[i];
  j["noise_std"] = noise;
  j["noise_std_assumed"] = false;  // kept for readers of version 1: never assumed now
  j["noise_std_source"] =
      r.noise_source == "the model's reading_std" ? "reading_std" : r.noise_source;
  j["partial"] = r.partial;
  j["stopped_in"] = r.partial ? Json(r.stopped_in) : Json();
  j["prior"] = setup.has_prior;
  j["existing_readings"] = setup.existing_readings;
  j["exchange"] = {{"passes", result.passes},
                   {"exchanges", result.exchanges},
                   {"greedy_value", number(result.greedy_value)},
                   {"value", number(result.criterion_value)},
                   {"random_value", number(criterion_value(
                                        design.criterion,
                                        design_information(candidates, r.random, setup), setup))}};
  if (std::isfinite(bound.bound))
    j["exchange"]["bound"] = {{"value", number(bound.bound)},
                              {"relaxed_value", number(bound.relaxed_value)},
                              {"iterations", bound.iterations},
                              {"std_ratio", number(r.std_ratio)}};
  j["parameters"] = Json::array();
  for (std::size_t c = 0; c < setup.free_indices.size(); ++c) {
    const Parameter& p = model.parameters()[setup.free_indices[c]];
    const auto k = static_cast<Eigen::Index>(c);
    j["parameters"].push_back({{"name", p.name},
                               {"unit", p.unit},
                               {"designed_std", number(std::sqrt(r.designed_cov(k, k)))},
                               {"random_std", number(std::sqrt(r.random_cov(k, k)))},
                               {"nominal_std", setup.scale[k]}});
  }
  j["predicted_pose_error"] = {{"workspace_samples", r.designed_pose.samples},
                               {"designed", to_json(r.designed_pose)},
                               {"random", to_json(r.random_pose)},
                               {"nominal", to_json(r.nominal_pose)}};
  // For the page's plots: the error at each workspace sample, the criterion after each
  // exchange pass and where the chosen configurations lie among the candidates.
  j["predicted_pose_error"]["position_1sigma_mm_per_sample"] = {
      {"designed", r.designed_pose.position_1sigma},
      {"random", r.random_pose.position_1sigma},
      {"nominal", r.nominal_pose.position_1sigma}};
  j["exchange"]["pass_values"] = result.pass_values;
  j["configuration_map"] = to_json(design_configuration_map(candidates, result.chosen));
  if (!target.is_null()) j["target"] = target;
  j["template"] = template_path;
  return j;
}

std::string design_template_csv(const ExperimentDesignResult& r) {
  const MeasurementModel& model = *r.model;
  const DesignOptions& design = r.options;
  const std::string heading =
      "# kincal design: " + printable(r.model_file) + ", criterion " + to_string(design.criterion) +
      " (" + criterion_meaning(design.criterion, design.orientation_length) + "), " +
      std::to_string(design.count) + " measurements in " + std::to_string(r.rows.size()) +
      " configurations, seed " + std::to_string(design.seed) +
      "\n# fill in the empty reading columns with the measured " + "values" +
      (model.sensors().size() > 1
           ? " of the sensors each row's '# read:' line names (leave the others empty)"
           : "") +
      ", then: kincal calibrate --model " + printable(r.model_file) + " --data <this file>\n" +
      (r.partial ? "# PARTIAL: interrupted in the " + r.stopped_in +
                       ": the best design found before the interruption\n"
                 : "");
  return template_csv(model, r.rows, heading);
}

}  // namespace kincal
