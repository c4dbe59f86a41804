// kincal compare: a model (a calibration's result) against a known truth (a simulation's
// <stem>.truth.json): the error of each parameter, and the error of the mechanism's pose over
// a set of configurations, in text, JSON and HTML. Closes the design loop: design ->
// simulate --configs -> calibrate -> compare.

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/html_pages.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/cli/model_pair.hpp"
#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::cli {

namespace {

using Json = nlohmann::ordered_json;

struct ParameterError {
  std::string name, unit;
  double truth = 0, estimate = 0, error = 0;
  bool free = false;
};

struct PoseErrors {
  std::vector<double> position, orientation;  // per configuration; NaN where unreachable
  int fk_failures = 0;
  double position_mean = 0, position_rms = 0, position_max = 0;
  double orientation_mean = 0, orientation_rms = 0, orientation_max = 0;
};

PoseErrors pose_errors(const MeasurementModel& truth_model, const VectorXd& truth,
                       const MeasurementModel& model, const VectorXd& estimate,
                       const MatrixXd& configurations) {
  PoseErrors out;
  const Mechanism& tm = truth_model.mechanism();
  const Mechanism& em = model.mechanism();
  int ok = 0;
  for (int j = 0; j < configurations.rows(); ++j) {
    const VectorXd q = configurations.row(j).transpose();
    const ForwardKinematicsResult t =
        tm.forward_kinematics(truth.head(tm.num_parameters()), q, tm.home_pose(),
                              truth_model.forward_kinematics_options());
    const ForwardKinematicsResult e = em.forward_kinematics(
        estimate.head(em.num_parameters()), q, em.home_pose(), model.forward_kinematics_options());
    if (!t.ok() || !e.ok()) {
      ++out.fk_failures;
      out.position.push_back(std::numeric_limits<double>::quiet_NaN());
      out.orientation.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const double dp = position_error(t.pose, e.pose), dr = orientation_error(t.pose, e.pose);
    out.position.push_back(dp);
    out.orientation.push_back(dr);
    out.position_mean += dp;
    out.position_rms += dp * dp;
    out.orientation_mean += dr;
    out.orientation_rms += dr * dr;
    out.position_max = std::max(out.position_max, dp);
    out.orientation_max = std::max(out.orientation_max, dr);
    ++ok;
  }
  if (ok > 0) {
    out.position_mean /= ok;
    out.orientation_mean /= ok;
    out.position_rms = std::sqrt(out.position_rms / ok);
    out.orientation_rms = std::sqrt(out.orientation_rms / ok);
  }
  return out;
}

Json number(double v) { return std::isfinite(v) ? Json(v) : Json(); }

}  // namespace

int run_compare(const Args& args) {
  po::options_description options("kincal compare");
  options.add_options()("truth", po::value<std::string>(),
                        "the true model (a model file, e.g. simulate --write-data's "
                        "<stem>.truth.json)")(
      "model", po::value<std::string>(),
      "the model to judge (e.g. calibrate --out's), with the same parameters as --truth")(
      "data", po::value<std::string>(),
      "compare the poses at the configurations of this measurement file (its actuator "
      "columns; readings are not used) instead of a sample of the workspace")(
      "poses", po::value<int>()->default_value(200),
      "workspace configurations drawn in the truth's actuator box (without --data)")(
      "seed", po::value<Seed>()->default_value(Seed{1}, "1"),
      "random seed of the workspace sample")(
      "html", po::value<std::string>(),
      "write the comparison for people to FILE: one self-contained HTML page");
  add_json_option(options, "the comparison");
  add_data_size_option(options);
  po::variables_map vm;
  if (!parse_command_line("compare", args, options, vm)) return 0;
  if (!vm.count("truth")) throw CliError("--truth FILE is required (the true model)");
  if (!vm.count("model")) throw CliError("--model FILE is required (the model to judge)");
  const int poses = vm["poses"].as<int>();
  if (vm.count("data") && !vm["poses"].defaulted())
    throw CliError("--data gives the configurations: give it without --poses");
  if (poses < 1) throw CliError("--poses must be at least 1");
  if (poses > 1000000) throw CliError("--poses must be at most 1000000");
  OutputPlan plan;
  for (const char* option : {"truth", "model", "data"})
    if (vm.count(option)) plan.input(std::string("--") + option, vm[option].as<std::string>());
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  if (vm.count("html")) plan.output("--html", vm["html"].as<std::string>());
  plan.check();

  const std::string truth_file = vm["truth"].as<std::string>();
  const std::string model_file = vm["model"].as<std::string>();
  const std::shared_ptr<MeasurementModel> truth_model = load_model_file(truth_file);
  const std::shared_ptr<MeasurementModel> model = load_model_option(vm);
  check_same_parameters(*truth_model, "--truth " + printable(truth_file), *model,
                        "--model " + printable(model_file));
  const VectorXd truth = truth_model->parameters().nominal_values();
  const VectorXd estimate = model->parameters().nominal_values();

  // Parameters: those free in --model and those whose values differ.
  std::vector<ParameterError> parameters;
  for (int i = 0; i < model->parameters().size(); ++i) {
    const Parameter& p = model->parameters()[i];
    ParameterError e{p.name, p.unit, truth[i], estimate[i], estimate[i] - truth[i], p.free};
    if (p.unit == kRadian) e.error = wrap_angle(e.error);
    if (!p.free && e.error == 0) continue;
    parameters.push_back(e);
  }
  std::map<std::string, std::pair<double, int>> rms_by_unit;  // sum of squares, count
  std::map<std::string, const ParameterError*> worst_by_unit;
  for (const auto& p : parameters) {
    auto& [sum, count] = rms_by_unit[p.unit];
    sum += p.error * p.error;
    ++count;
    const ParameterError*& worst = worst_by_unit[p.unit];
    if (!worst || std::abs(p.error) > std::abs(worst->error)) worst = &p;
  }

  // Configurations: --data's actuator columns, or a sample of the truth's workspace.
  MatrixXd configurations;
  std::string where;
  if (vm.count("data")) {
    const std::string path = vm["data"].as<std::string>();
    MeasurementTable table;
    try {
      table = read_model_columns(path, *model, data_limits(vm));
    } catch (const std::invalid_argument& e) {
      throw measurement_file_error(e);
    }
    configurations = table.data.actuators;
    where =
        "the " + std::to_string(configurations.rows()) + " configurations of " + printable(path);
  } else {
    try {
      configurations =
          sample_workspace(*truth_model, truth, {}, poses, vm["seed"].as<Seed>().value).actuators;
    } catch (const std::exception& e) {
      throw CliError("--truth " + printable(truth_file) +
                     ": cannot sample its workspace: " + e.what());
    }
    where = std::to_string(poses) + " configurations drawn in the workspace (seed " +
            std::to_string(vm["seed"].as<Seed>().value) + ")";
  }
  const PoseErrors pose = pose_errors(*truth_model, truth, *model, estimate, configurations);
  if (pose.fk_failures == configurations.rows())
    throw CliError("forward kinematics fails at every configuration (" + where +
                   ") with the truth or the model; expected configurations both reach");
  for (double v : {pose.position_mean, pose.position_rms, pose.position_max, pose.orientation_mean,
                   pose.orientation_rms, pose.orientation_max})
    if (!std::isfinite(v))
      throw CliError("the pose errors are not finite; expected models of a real machine");

  Json j = json_document("kincal-compare");
  j["truth"] = truth_file;
  j["model"] = model_file;
  j["parameters"] = Json::array();
  for (const auto& p : parameters)
    j["parameters"].push_back({{"name", p.name},
                               {"unit", p.unit},
                               {"free", p.free},
                               {"truth", p.truth},
                               {"estimate", p.estimate},
                               {"error", p.error}});
  j["parameter_error"] = Json::object();
  for (const auto& [unit, sc] : rms_by_unit)
    j["parameter_error"][unit] = {{"count", sc.second},
                                  {"rms", std::sqrt(sc.first / sc.second)},
                                  {"max_abs", std::abs(worst_by_unit[unit]->error)},
                                  {"max_abs_parameter", worst_by_unit[unit]->name}};
  j["pose_error"] = {{"configurations", configurations.rows()},
                     {"source", vm.count("data") ? "data" : "workspace"},
                     {"data", vm.count("data") ? Json(vm["data"].as<std::string>()) : Json()},
                     {"seed", vm.count("data") ? Json() : Json(vm["seed"].as<Seed>().value)},
                     {"position_mean_mm", pose.position_mean},
                     {"position_rms_mm", pose.position_rms},
                     {"position_max_mm", pose.position_max},
                     {"orientation_mean_rad", pose.orientation_mean},
                     {"orientation_rms_rad", pose.orientation_rms},
                     {"orientation_max_rad", pose.orientation_max},
                     {"fk_failures", pose.fk_failures}};
  Json per = Json::array();
  for (std::size_t c = 0; c < pose.position.size(); ++c)
    per.push_back({{"configuration", c + 1},
                   {"position_mm", number(pose.position[c])},
                   {"orientation_rad", number(pose.orientation[c])}});
  j["pose_error"]["per_configuration"] = per;

  const bool quiet = (!json_file.empty() && plan.to_stdout("--json")) ||
                     (vm.count("html") && plan.to_stdout("--html"));
  if (!quiet) {
    out() << format_text("kincal compare: %s against the truth %s\n", printable(model_file).c_str(),
                         printable(truth_file).c_str());
    out() << format_text("parameters (error = estimate - truth; %zu free or different):\n",
                         parameters.size());
    out() << format_text("  %-24s %-4s %14s %14s %12s\n", "name", "unit", "truth", "estimate",
                         "error");
    for (const auto& p : parameters)
      out() << format_text("  %-24s %-4s %14.8g %14.8g %12.4g\n", printable(p.name).c_str(),
                           p.unit.c_str(), p.truth, p.estimate, p.error);
    for (const auto& [unit, sc] : rms_by_unit)
      out() << format_text(
          "parameter error RMS %.4g %s over %d parameters (largest: %s, %.4g %s)\n",
          std::sqrt(sc.first / sc.second), unit.c_str(), sc.second,
          printable(worst_by_unit[unit]->name).c_str(), worst_by_unit[unit]->error, unit.c_str());
    out() << format_text("pose error over %s:\n", where.c_str());
    out() << format_text("  position    mean %.6g mm  RMS %.6g mm  max %.6g mm\n",
                         pose.position_mean, pose.position_rms, pose.position_max);
    out() << format_text("  orientation mean %.4e rad  RMS %.4e rad  max %.4e rad\n",
                         pose.orientation_mean, pose.orientation_rms, pose.orientation_max);
    if (pose.fk_failures)
      out() << format_text("  %d configurations unreachable by the truth or the model (left out)\n",
                           pose.fk_failures);
  }
  std::vector<std::pair<std::string, std::string>> outputs;
  if (!json_file.empty()) outputs.push_back({"--json", j.dump(2) + "\n"});
  if (vm.count("html")) outputs.push_back({"--html", render_compare_html(j)});
  plan.write(outputs);
  return 0;
}

}  // namespace kincal::cli
