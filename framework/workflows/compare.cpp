#include "kincal/framework/workflows/compare.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "kincal/framework/analysis/pose_accuracy.hpp"
#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/kinematics/model_pair.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

using Json = nlohmann::ordered_json;

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

CompareResult compare_models(const CompareRequest& request) {
  if (!request.truth || !request.model)
    throw std::invalid_argument("compare: the request needs a truth and a model");
  const MeasurementModel& truth_model = *request.truth;
  const MeasurementModel& model = *request.model;
  check_same_parameters(truth_model, "--truth " + printable(request.truth_file), model,
                        "--model " + printable(request.model_file));
  const VectorXd truth = truth_model.parameters().nominal_values();
  const VectorXd estimate = model.parameters().nominal_values();
  CompareResult result;
  result.truth_file = request.truth_file;
  result.model_file = request.model_file;
  result.data_file = request.data_file;
  result.seed = request.seed;

  // Parameters: those free in the model and those whose values differ.
  for (int i = 0; i < model.parameters().size(); ++i) {
    const Parameter& p = model.parameters()[i];
    ParameterError e{p.name, p.unit, truth[i], estimate[i], estimate[i] - truth[i], p.free};
    if (p.unit == kRadian) e.error = wrap_angle(e.error);
    if (!p.free && e.error == 0) continue;
    result.parameters.push_back(e);
  }
  for (const ParameterError& p : result.parameters) {
    UnitParameterError& u = result.by_unit[p.unit];
    u.rms += p.error * p.error;  // a sum of squares until the end
    ++u.count;
    if (u.max_abs_parameter.empty() || std::abs(p.error) > u.max_abs) {
      u.max_abs = std::abs(p.error);
      u.max_abs_parameter = p.name;
    }
  }
  for (auto& [unit, u] : result.by_unit) u.rms = std::sqrt(u.rms / u.count);

  // Configurations: the data's actuator columns, or a sample of the truth's workspace.
  MatrixXd configurations = request.configurations;
  result.from_data = configurations.rows() > 0;
  if (result.from_data) {
    result.where = "the " + std::to_string(configurations.rows()) + " configurations of " +
                   printable(request.data_file);
  } else {
    if (request.workspace_poses < 1 || request.workspace_poses > 1000000)
      throw std::invalid_argument(
          "the number of workspace configurations must be from 1 to 1000000");
    try {
      configurations =
          sample_workspace(truth_model, truth, {}, request.workspace_poses, request.seed).actuators;
    } catch (const std::exception& e) {
      throw std::invalid_argument("--truth " + printable(request.truth_file) +
                                  ": cannot sample its workspace: " + e.what());
    }
    result.where = std::to_string(request.workspace_poses) +
                   " configurations drawn in the workspace (seed " + std::to_string(request.seed) +
                   ")";
  }
  result.configurations = static_cast<int>(configurations.rows());
  result.pose = pose_errors(truth_model, truth, model, estimate, configurations);
  const PoseErrors& pose = result.pose;
  if (pose.fk_failures == configurations.rows())
    throw std::invalid_argument(
        "forward kinematics fails at every configuration (" + result.where +
        ") with the truth or the model; expected configurations both reach");
  for (double v : {pose.position_mean, pose.position_rms, pose.position_max, pose.orientation_mean,
                   pose.orientation_rms, pose.orientation_max})
    if (!std::isfinite(v))
      throw std::invalid_argument(
          "the pose errors are not finite; expected models of a real machine");
  return result;
}

nlohmann::ordered_json comparison_json(const CompareResult& result) {
  Json j = {{"format", "kincal-compare"}, {"version", 1}};
  j["truth"] = result.truth_file;
  j["model"] = result.model_file;
  j["parameters"] = Json::array();
  for (const auto& p : result.parameters)
    j["parameters"].push_back({{"name", p.name},
                               {"unit", p.unit},
                               {"free", p.free},
                               {"truth", p.truth},
                               {"estimate", p.estimate},
                               {"error", p.error}});
  j["parameter_error"] = Json::object();
  for (const auto& [unit, u] : result.by_unit)
    j["parameter_error"][unit] = {{"count", u.count},
                                  {"rms", u.rms},
                                  {"max_abs", u.max_abs},
                                  {"max_abs_parameter", u.max_abs_parameter}};
  const PoseErrors& pose = result.pose;
  j["pose_error"] = {{"configurations", result.configurations},
                     {"source", result.from_data ? "data" : "workspace"},
                     {"data", result.from_data ? Json(result.data_file) : Json()},
                     {"seed", result.from_data ? Json() : Json(result.seed)},
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
  return j;
}

std::string comparison_text(const CompareResult& result) {
  std::string out;
  out += format_text("kincal compare: %s against the truth %s\n",
                     printable(result.model_file).c_str(), printable(result.truth_file).c_str());
  out += format_text("parameters (error = estimate - truth; %zu free or different):\n",
                     result.parameters.size());
  out += format_text("  %-24s %-4s %14s %14s %12s\n", "name", "unit", "truth", "estimate", "error");
  for (const auto& p : result.parameters)
    out += format_text("  %-24s %-4s %14.8g %14.8g %12.4g\n", printable(p.name).c_str(),
                       p.unit.c_str(), p.truth, p.estimate, p.error);
  for (const auto& [unit, u] : result.by_unit) {
    // The largest error with its sign, as the parameters' table shows it.
    double signed_max = u.max_abs;
    for (const auto& p : result.parameters)
      if (p.name == u.max_abs_parameter) signed_max = p.error;
    out += format_text("parameter error RMS %.4g %s over %d parameters (largest: %s, %.4g %s)\n",
                       u.rms, unit.c_str(), u.count, printable(u.max_abs_parameter).c_str(),
                       signed_max, unit.c_str());
  }
  const PoseErrors& pose = result.pose;
  out += format_text("pose error over %s:\n", result.where.c_str());
  out += format_text("  position    mean %.6g mm  RMS %.6g mm  max %.6g mm\n", pose.position_mean,
                     pose.position_rms, pose.position_max);
  out += format_text("  orientation mean %.4e rad  RMS %.4e rad  max %.4e rad\n",
                     pose.orientation_mean, pose.orientation_rms, pose.orientation_max);
  if (pose.fk_failures)
    out += format_text("  %d configurations unreachable by the truth or the model (left out)\n",
                       pose.fk_failures);
  return out;
}

}  // namespace kincal
