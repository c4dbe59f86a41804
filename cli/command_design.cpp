// kincal design: chooses the configurations (and, for a model with several sensors, the
// sensor placements) to measure, and writes them as a measurement template that calibrate
// reads once the readings are filled in.

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <set>
#include <sstream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/design_map.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/memory_check.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/progress.hpp"
#include "kincal/cli/shared_options.hpp"
#include "kincal/cli/simulation_report.hpp"
#include "kincal/cli/target_accuracy.hpp"
#include "kincal/framework/analysis/identifiability_check.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/design/experiment_design.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

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

// n x n matrices design holds at once, at most: the prior and existing data, the workspace
// weight, the exchange's M, M^-1, M0 and W, a criterion's eigenvectors and inverse, the
// covariances compared, and temporaries.
constexpr double kDesignMatrices = 16;

// The information matrix M (normalised parameters) must determine every free parameter:
// finite, and of full numerical rank, with its square root's columns scaled as calibrate
// scales the Jacobian's. Throws CliError "<what>: <the deficiency>; <remedy>" otherwise.
void check_information(const MatrixXd& M, const std::vector<std::string>& names,
                       const std::string& what, const std::string& remedy) {
  const int n = static_cast<int>(M.rows());
  if (!M.allFinite())
    throw CliError(what +
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
  if (a.rank_deficient()) throw CliError(what + ": " + describe_deficiency(a) + "; " + remedy);
}

// The reading noise std per reading: --noise-std per unit, else the model's reading_std;
// neither is an error (a design weighs the readings against each other and against the
// prior by it, and its predictions scale with it: no value is a safe guess).
VectorXd design_noise_std(const po::variables_map& vm, const MeasurementModel& model,
                          const std::string& model_file) {
  if (!vm.count("noise-std") && !model.weighted())
    throw CliError((model_file.empty() ? std::string("the model") : printable(model_file)) +
                   " states no reading_std: give the readings' noise std, e.g. --noise-std "
                   "0.0072mm (or reading_std in the model file)");
  return noise_std_per_reading(vm, model);
}

void apply_config_range(const po::variables_map& vm, MeasurementModel& model) {
  if (!vm.count("config-range")) return;
  const UnitValues range = unit_values_option(vm, "config-range");
  for (const Actuator& a : model.mechanism().actuators())
    if (range.has(a.unit)) model.set_actuator_range(a.name, range.get(a.unit));
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

void print_prediction_row(const char* label, double designed, double random, double nominal) {
  out() << format_text("  %-34s %s %s %s\n", label, figure(designed).c_str(),
                       figure(random).c_str(), figure(nominal).c_str());
}

}  // namespace

int run_design(const Args& args) {
  po::options_description options("kincal design");
  options.add_options()("model", po::value<std::string>(), "model file (JSON)")(
      "poses", po::value<int>(), "number of configurations to choose")(
      "criterion", po::value<std::string>()->default_value("D"),
      "D (parameters' confidence volume), A (mean parameter variance), E (worst direction) or I "
      "(mean predicted position variance over the workspace)")(
      "candidates", po::value<int>()->default_value(10000),
      "random candidate configurations drawn in the box (the box's corners are added)")(
      "existing", po::value<std::string>(),
      "measurement file (CSV) already measured: its readings count as information, and the "
      "design adds to them")(
      "singularity-margin",
      po::value<double>()->default_value(DesignOptions{}.min_singularity_margin),
      "keep configurations whose conditioning is at least this fraction of home's")(
      "orientation-length", po::value<std::string>(),
      "criterion I only: also weigh the orientation error, a rotation of 1 rad counting as a "
      "displacement of this length, e.g. 300mm (the tool's reach; default: position only)")(
      "bound", po::bool_switch(),
      "also bound how good any design of --poses measurements from these candidates can be "
      "(D, A, I: the continuous relaxation's optimum, certified; a fraction of a second for "
      "10^4 hexapod candidates, 2 s for 10^5), and say how close the design comes to it")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"),
      "random seed (candidates, workspace samples, the random design compared with)")(
      "out", po::value<std::string>(), "write the measurement template (CSV) to FILE")(
      "html", po::value<std::string>(),
      "write the design for people to FILE: one self-contained HTML page");
  add_json_option(options, "the design");
  add_config_range_option(options);
  add_noise_std_option(options,
                       "weighs the readings in the design and scales its predictions (default: "
                       "the model's reading_std; one of them is required)");
  add_deprecated_alias(options, "count", "poses", po::value<int>());
  add_free_fix_options(options);
  add_prior_std_option(options);
  add_data_size_option(options);
  add_progress_option(options);
  add_target_option(options);
  po::variables_map vm;
  if (!parse_command_line("design", args, options, vm)) return 0;
  const std::optional<TargetAccuracy> target = target_option(vm);
  if (!vm.count("poses")) throw CliError("--poses N is required (the configurations to choose)");
  if (!vm.count("out")) throw CliError("--out FILE is required (the measurement template)");
  DesignOptions design;
  design.count = vm["poses"].as<int>();
  design.num_random = vm["candidates"].as<int>();
  design.seed = vm["seed"].as<Seed>().value;
  design.min_singularity_margin = vm["singularity-margin"].as<double>();
  try {
    design.criterion = parse_design_criterion(vm["criterion"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--criterion: ") + e.what());
  }
  if (design.count < 1) throw CliError("--poses must be at least 1");
  if (design.num_random < 0) throw CliError("--candidates must be >= 0");
  if (!(design.min_singularity_margin >= 0)) throw CliError("--singularity-margin must be >= 0");
  if (vm.count("orientation-length")) {
    if (design.criterion != DesignCriterion::kI)
      throw CliError("--orientation-length applies to --criterion I only");
    const UnitValues length = unit_values_option(vm, "orientation-length");
    if (length.values().size() != 1 || !length.has(kMillimetre))
      throw CliError("--orientation-length '" + vm["orientation-length"].as<std::string>() +
                     "': expected a length, e.g. 300mm");
    design.orientation_length = length.get(kMillimetre);
    if (!(design.orientation_length >= 0) || !std::isfinite(design.orientation_length))
      throw CliError("--orientation-length '" + vm["orientation-length"].as<std::string>() +
                     "': expected a finite length >= 0");
  }
  OutputPlan plan;
  for (const char* option : {"model", "existing"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  if (plan.to_stdout("--out")) throw CliError("--out needs a file name (the template)");
  if (vm.count("json")) plan.output("--json", vm["json"].as<std::string>());
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  const std::string model_file = vm.count("model") ? vm["model"].as<std::string>() : "";
  std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  apply_free_fix(vm, *model);
  apply_prior_std(vm, *model);
  apply_config_range(vm, *model);
  const int n = model->parameters().num_free();
  if (n == 0) throw CliError("no free parameters: nothing to design for (use --free)");
  design.noise_std = design_noise_std(vm, *model, model_file);
  const char* noise_source = vm.count("noise-std") ? "--noise-std" : "the model's reading_std";
  // The n x n matrices first (a model of 10^4 free parameters needs GBs of them), then the
  // candidates' rows beside them: the exchange keeps each row, its transpose and M^-1 times
  // it (and W M^-1 times it for A and I), and the workspace samples hold 6 rows each.
  const double matrix_bytes =
      kDesignMatrices * 8.0 * n * n + 8.0 * 6 * n * DesignOptions{}.workspace_samples;
  check_memory_square((model_file.empty() ? std::string("the model") : model_file) + " (" +
                          std::to_string(n) + " free parameters)",
                      n, kDesignMatrices, "free parameter",
                      8.0 * 6 * n * DesignOptions{}.workspace_samples);
  check_memory("--candidates " + std::to_string(design.num_random), design.num_random,
               kConfigurationBytes + 8.0 * model->num_readings() * (4.0 * n + 2 * 16 + 2),
               "candidate", matrix_bytes);

  const VectorXd nominal = model->parameters().nominal_values();
  Measurements existing;
  if (vm.count("existing")) {
    const LoadedData loaded = load_measurements("design", vm["existing"].as<std::string>(), *model,
                                                nominal, false, model_file, data_limits(vm));
    note_copied_rows("design", loaded);
    existing = loaded.data;
  }
  DesignSetup setup = make_design_setup(*model, design, vm.count("existing") ? &existing : nullptr);
  // Progress per stage on stderr (each stage's own count and time left), and Ctrl-C: the
  // first one stops the work with the best design so far (marked partial, exit 130), the
  // second one aborts.
  const bool show_progress = progress_wanted(vm);
  std::unique_ptr<Progress> progress;
  std::string progress_stage, stopped_in;
  long progress_done = 0;
  std::chrono::steady_clock::time_point exchange_start;
  const InterruptGuard interrupt_guard("design");
  design.monitor = [&](const DesignStep& step) {
    const std::string stage =
        step.pass ? std::string(step.stage) + " pass " + std::to_string(step.pass) : step.stage;
    if (show_progress && stage != progress_stage) {
      if (progress) progress->finish();
      const std::string unit =
          std::string(step.stage) == "candidates" ? "candidates drawn"
          : std::string(step.stage) == "greedy"   ? "measurements picked (greedy start)"
          : std::string(step.stage) == "bound"
              ? "bound iterations (at most)"
              : "measurements revisited (exchange pass " + std::to_string(step.pass) + ")";
      // A stage shows after a second: quick designs stay quiet. The exchange's passes count
      // that second from the exchange's start, so a long exchange of short passes shows.
      const auto now = std::chrono::steady_clock::now();
      if (std::string(step.stage) == "exchange" && step.pass == 1) exchange_start = now;
      const double delay =
          std::string(step.stage) == "exchange"
              ? std::max(0.0, 1.0 - std::chrono::duration<double>(now - exchange_start).count())
              : 1.0;
      progress = std::make_unique<Progress>("design", step.total, unit, true, delay);
      progress_stage = stage;
      progress_done = 0;
    }
    if (progress && step.done > progress_done) {
      progress->advance(step.done - progress_done);
      progress_done = step.done;
    }
    if (!interrupt_requested()) return true;
    if (stopped_in.empty()) stopped_in = stage;
    return false;
  };
  const DesignCandidates candidates = make_design_candidates(*model, setup, design);
  if (candidates.stopped && candidates.size() < design.count) {
    if (progress) progress->finish();
    err() << format_text(
        "kincal design: interrupted while drawing candidates: %d reachable so far, "
        "fewer than --poses %d; nothing written\n",
        candidates.size(), design.count);
    return 130;  // the shell's code for a run ended by SIGINT
  }
  if (candidates.size() < design.count)
    throw CliError("only " + std::to_string(candidates.size()) + " reachable candidates (" +
                   std::to_string(candidates.rejected_unreachable) + " unreachable, " +
                   std::to_string(candidates.rejected_singular) + " near-singular) for --poses " +
                   std::to_string(design.count) +
                   "; raise --candidates or lower --singularity-margin");
  const long long new_readings = [&] {
    long long k = 0;
    for (const auto& s : model->sensors()) k = std::max<long long>(k, s->num_readings());
    return k * design.count;
  }();
  if (!setup.has_prior && setup.existing_readings + new_readings < n)
    throw CliError("--poses " + std::to_string(design.count) + " gives at most " +
                   std::to_string(new_readings + setup.existing_readings) + " readings for " +
                   std::to_string(n) +
                   " free parameters; expected at least as many readings as free parameters");
  std::vector<std::string> free_names;
  for (int i : setup.free_indices) free_names.push_back(model->parameters()[i].name);
  // No design from these candidates can determine more than all of them together: a
  // parameter no reading sees, or a box of 0 (every candidate at home), is an error here,
  // not a template of copies of home with a criterion of -inf.
  check_information(setup.base_information + candidates.rows.transpose() * candidates.rows,
                    free_names,
                    "no design of these " + std::to_string(candidates.size()) +
                        " candidates determines every free parameter",
                    "widen the box (--config-range), fix the parameters (--fix) or state a prior "
                    "(--prior-std)");
  const DesignResult result = choose_design(candidates, setup, design);
  check_information(design_information(candidates, result.chosen, setup), free_names,
                    "the " + std::to_string(design.count) +
                        " measurements chosen do not determine every free parameter",
                    "raise --poses, widen the box (--config-range) or state a prior "
                    "(--prior-std)");
  if (!std::isfinite(result.criterion_value))
    throw CliError("the design's criterion " + std::string(to_string(design.criterion)) + " is " +
                   (std::isnan(result.criterion_value) ? "not a number"
                                                       : std::to_string(result.criterion_value)) +
                   "; expected a finite value (a reading noise std on the scale of the readings, "
                   "a box the readings see)");
  const bool want_bound = vm["bound"].as<bool>();
  if (want_bound && design.criterion == DesignCriterion::kE)
    note("design", "--bound: the E criterion is not smooth; no bound is computed for it");
  const DesignBound bound = want_bound && !result.stopped && !candidates.stopped
                                ? design_bound(candidates, setup, design, result.chosen)
                                : DesignBound{};
  if (progress) progress->finish();
  const bool partial = candidates.stopped || result.stopped || bound.stopped;
  const double std_ratio =
      design_std_ratio_to_bound(design.criterion, result.criterion_value, bound, n);
  const Measurements rows = design_rows(*model, candidates, result.chosen);
  const std::vector<int> random = random_design(candidates, design.count, design.seed);

  const MatrixXd designed_cov =
      design_covariance(design_information(candidates, result.chosen, setup), setup);
  const MatrixXd random_cov =
      design_covariance(design_information(candidates, random, setup), setup);
  if (!random_cov.allFinite())
    note("design",
         "the random design compared with does not determine every free parameter: "
         "its predictions are n/a (null in the JSON)");
  const MatrixXd nominal_cov = setup.scale.array().square().matrix().asDiagonal();
  const PoseErrorPrediction designed_pose = predict_pose_errors(setup.workspace, designed_cov);
  const PoseErrorPrediction random_pose = predict_pose_errors(setup.workspace, random_cov);
  const PoseErrorPrediction nominal_pose = predict_pose_errors(setup.workspace, nominal_cov);

  const std::vector<int> free = setup.free_indices;
  const char* criterion = to_string(design.criterion);
  char noise_text[200] = "";
  {
    std::string t;
    const auto names = model->reading_names();
    const auto units = model->reading_units();
    std::set<std::string> seen;
    for (int i = 0; i < model->num_readings(); ++i) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %g %s", t.empty() ? "" : ", ", names[i].c_str(),
                    setup.noise_std[i], units[i].c_str());
      if (seen.insert(names[i]).second && t.size() < 150) t += buf;
    }
    std::snprintf(noise_text, sizeof noise_text, "%s", t.c_str());
  }
  const std::string heading =
      "# kincal design: " + printable(model_file) + ", criterion " + criterion + " (" +
      criterion_meaning(design.criterion, design.orientation_length) + "), " +
      std::to_string(design.count) + " measurements in " + std::to_string(rows.size()) +
      " configurations, seed " + std::to_string(design.seed) +
      "\n# fill in the empty reading columns with the measured " + "values" +
      (model->sensors().size() > 1
           ? " of the sensors each row's '# read:' line names (leave the others empty)"
           : "") +
      ", then: kincal calibrate --model " + printable(model_file) + " --data <this file>\n" +
      (partial ? "# PARTIAL: interrupted in the " + stopped_in +
                     ": the best design found before the interruption\n"
               : "");

  const bool json_to_stdout = (vm.count("json") && plan.to_stdout("--json")) ||
                              (vm.count("html") && plan.to_stdout("--html"));
  if (!json_to_stdout) {
    out() << format_text(
        "kincal design: %s, criterion %s, %d measurements in %d configurations, seed %llu\n",
        printable(model_file).c_str(), criterion, design.count, rows.size(),
        static_cast<unsigned long long>(design.seed));
    out() << format_text(
        "candidates: %d (%d box corners + random; rejected: %d unreachable, %d below the "
        "singularity margin %g)\n",
        candidates.size(), candidates.num_corners, candidates.rejected_unreachable,
        candidates.rejected_singular, design.min_singularity_margin);
    out() << format_text("exchange: %d passes, %d exchanges; criterion %s: greedy %.6g -> %.6g\n",
                         result.passes, result.exchanges, criterion, result.greedy_value,
                         result.criterion_value);
    if (std::isfinite(bound.bound))
      out() << format_text(
          "bound: no design of %d from these candidates has criterion %s %s %.6g (certified "
          "after %d iterations); this design's %s are within %.2f %% of the best possible\n",
          design.count, criterion, design.criterion == DesignCriterion::kD ? "above" : "below",
          bound.bound, bound.iterations,
          design.criterion == DesignCriterion::kD   ? "parameter stds (geometric mean)"
          : design.criterion == DesignCriterion::kI ? "predicted position errors (RMS)"
                                                    : "parameter stds (RMS, relative)",
          100 * (std_ratio - 1));
    out() << format_text(
        "prediction (linearised at the nominal values; reading noise std %s from %s%s%s):\n",
        noise_text, noise_source, setup.has_prior ? "; with the model's prior" : "",
        setup.existing_readings
            ? ("; with " + std::to_string(setup.existing_readings) + " existing readings").c_str()
            : "");
    out() << format_text("  %-34s %12s %12s %12s\n", "", "designed", "random", "nominal");
    print_prediction_row("position error RMS (mm)", designed_pose.position_rms,
                         random_pose.position_rms, nominal_pose.position_rms);
    print_prediction_row("position error mean 1sigma (mm)", designed_pose.position_mean_1sigma,
                         random_pose.position_mean_1sigma, nominal_pose.position_mean_1sigma);
    print_prediction_row("position error max 95% (mm)", designed_pose.position_max_95,
                         random_pose.position_max_95, nominal_pose.position_max_95);
    print_prediction_row("orientation error RMS (rad)", designed_pose.orientation_rms,
                         random_pose.orientation_rms, nominal_pose.orientation_rms);
    print_prediction_row("orientation error max 95% (rad)", designed_pose.orientation_max_95,
                         random_pose.orientation_max_95, nominal_pose.orientation_max_95);
    out() << format_text("predicted parameter std:\n  %-22s %-4s %12s %12s %12s\n", "name", "unit",
                         "designed", "random", "nominal");
    for (int c = 0; c < n; ++c) {
      const Parameter& p = model->parameters()[free[c]];
      out() << format_text("  %-22s %-4s %s %s %s\n", p.name.c_str(), p.unit.c_str(),
                           figure(std::sqrt(designed_cov(c, c))).c_str(),
                           figure(std::sqrt(random_cov(c, c))).c_str(),
                           figure(setup.scale[c]).c_str());
    }
    out() << format_text("template: %s (%d configurations; fill in the reading columns)\n",
                         vm["out"].as<std::string>().c_str(), rows.size());
    if (partial)
      out() << format_text("PARTIAL: interrupted in the %s; the design is the best found so far\n",
                           stopped_in.c_str());
    if (target)
      out() << format_text(
          "target: %s\n",
          predicted_target(*target, {{"designed", to_json(designed_pose)}}, "designed")["verdict"]
              .get<std::string>()
              .c_str());
  }

  std::vector<std::pair<std::string, std::string>> outputs;
  if (vm.count("json") || vm.count("html")) {
    Json j;
    j["format"] = "kincal-design";
    j["version"] = 1;
    j["model"] = model_file;
    j["criterion"] = criterion;
    j["criterion_meaning"] = criterion_meaning(design.criterion, design.orientation_length);
    if (design.criterion == DesignCriterion::kI)
      j["orientation_length_mm"] = design.orientation_length;
    j["count"] = design.count;
    j["configurations"] = rows.size();
    j["seed"] = design.seed;
    j["candidates"] = {{"total", candidates.size()},
                       {"corners", candidates.num_corners},
                       {"rejected_unreachable", candidates.rejected_unreachable},
                       {"rejected_singular", candidates.rejected_singular},
                       {"singularity_margin", design.min_singularity_margin}};
    Json noise = Json::object();
    for (int i = 0; i < model->num_readings(); ++i)
      noise[model->reading_names()[i]] = setup.noise_std[i];
    j["noise_std"] = noise;
    j["noise_std_assumed"] = false;  // kept for readers of version 1: never assumed now
    j["noise_std_source"] = vm.count("noise-std") ? "--noise-std" : "reading_std";
    j["partial"] = partial;
    j["stopped_in"] = partial ? Json(stopped_in) : Json();
    j["prior"] = setup.has_prior;
    j["existing_readings"] = setup.existing_readings;
    j["exchange"] = {{"passes", result.passes},
                     {"exchanges", result.exchanges},
                     {"greedy_value", number(result.greedy_value)},
                     {"value", number(result.criterion_value)},
                     {"random_value", number(criterion_value(
                                          design.criterion,
                                          design_information(candidates, random, setup), setup))}};
    if (std::isfinite(bound.bound))
      j["exchange"]["bound"] = {{"value", number(bound.bound)},
                                {"relaxed_value", number(bound.relaxed_value)},
                                {"iterations", bound.iterations},
                                {"std_ratio", number(std_ratio)}};
    j["parameters"] = Json::array();
    for (int c = 0; c < n; ++c) {
      const Parameter& p = model->parameters()[free[c]];
      j["parameters"].push_back({{"name", p.name},
                                 {"unit", p.unit},
                                 {"designed_std", number(std::sqrt(designed_cov(c, c)))},
                                 {"random_std", number(std::sqrt(random_cov(c, c)))},
                                 {"nominal_std", setup.scale[c]}});
    }
    j["predicted_pose_error"] = {{"workspace_samples", designed_pose.samples},
                                 {"designed", to_json(designed_pose)},
                                 {"random", to_json(random_pose)},
                                 {"nominal", to_json(nominal_pose)}};
    // For the page's plots: the error at each workspace sample, the criterion after each
    // exchange pass and where the chosen configurations lie among the candidates.
    j["predicted_pose_error"]["position_1sigma_mm_per_sample"] = {
        {"designed", designed_pose.position_1sigma},
        {"random", random_pose.position_1sigma},
        {"nominal", nominal_pose.position_1sigma}};
    j["exchange"]["pass_values"] = result.pass_values;
    j["configuration_map"] = design_configuration_map(candidates, result.chosen);
    if (target) j["target"] = predicted_target(*target, j["predicted_pose_error"], "designed");
    j["template"] = vm["out"].as<std::string>();
    if (vm.count("json")) outputs.push_back({"--json", j.dump(2) + "\n"});
    if (vm.count("html")) outputs.push_back({"--html", render_design_html(j)});
  }
  outputs.push_back({"--out", template_csv(*model, rows, heading)});
  plan.write(outputs);
  if (partial) {
    err() << format_text(
        "kincal design: interrupted in the %s: wrote the best design found so far, "
        "marked partial (a full run may do better)\n",
        stopped_in.c_str());
    return 130;  // the shell's code for a run ended by SIGINT
  }
  return 0;
}

}  // namespace kincal::cli
