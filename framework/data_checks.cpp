#include "kincal/framework/data_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "kincal/framework/pose.hpp"
#include "kincal/framework/units.hpp"

namespace kincal {

namespace {

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

double rotation_angle(const Matrix3d& a, const Matrix3d& b) {
  return log_so3(a.transpose() * b).norm();
}

}  // namespace

HomePoseCheck check_poses_near_home(const MeasurementModel& model, const VectorXd& params,
                                    const Measurements& data) {
  HomePoseCheck check;
  const Mechanism& mechanism = model.mechanism();
  const Pose& home = mechanism.home_pose();
  const auto mechanism_params = params.head(static_cast<int>(mechanism.parameters().size()));
  std::vector<Pose> poses;
  for (int row = 0; row < data.size(); ++row) {
    const VectorXd q = data.actuators.row(row).transpose();
    const ForwardKinematicsResult fk =
        mechanism.forward_kinematics(mechanism_params, q, home, model.forward_kinematics_options());
    if (fk.ok()) poses.push_back(fk.pose);
  }
  check.poses = static_cast<int>(poses.size());
  if (poses.empty()) return check;
  Vector3d centre = Vector3d::Zero();
  for (const Pose& p : poses) centre += p.translation;
  centre /= static_cast<double>(poses.size());
  std::size_t central = 0;
  check.nearest_position_mm = check.nearest_angle_rad = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double from_centre = (poses[i].translation - centre).norm();
    check.extent_mm = std::max(check.extent_mm, from_centre);
    if (from_centre < (poses[central].translation - centre).norm()) central = i;
    check.nearest_position_mm =
        std::min(check.nearest_position_mm, (poses[i].translation - home.translation).norm());
    check.nearest_angle_rad =
        std::min(check.nearest_angle_rad, rotation_angle(home.rotation, poses[i].rotation));
  }
  for (const Pose& p : poses)
    check.extent_angle_rad =
        std::max(check.extent_angle_rad, rotation_angle(poses[central].rotation, p.rotation));
  const bool far_position = check.nearest_position_mm > std::max(check.extent_mm, kHomeFarMm);
  const bool far_rotation = check.nearest_angle_rad > std::max(check.extent_angle_rad, kHomeFarRad);
  check.far = far_position || far_rotation;
  if (check.far)
    check.warning =
        "forward kinematics of the data lands far from the model's home_pose: the closest of " +
        std::to_string(check.poses) + " poses is " + format("%.4g", check.nearest_position_mm) +
        " mm and " + format("%.3g", check.nearest_angle_rad * 180 / M_PI) +
        " deg from it, while the poses themselves spread over " + format("%.4g", check.extent_mm) +
        " mm and " + format("%.3g", check.extent_angle_rad * 180 / M_PI) +
        " deg. Forward kinematics starts at home_pose and converges to the nearest assembly of "
        "the mechanism, so a wrong home_pose silently gives other valid poses: check home_pose "
        "against the machine (kincal fk on a row whose pose you know)";
  return check;
}

std::string encoder_stroke_hint(const MeasurementModel& model, const VectorXd& params,
                                const Measurements& data, int failed_rows) {
  if (data.size() == 0 || 2 * failed_rows < data.size()) return "";
  const Mechanism& mechanism = model.mechanism();
  const auto mechanism_params = params.head(static_cast<int>(mechanism.parameters().size()));
  VectorXd home_q(static_cast<int>(mechanism.actuators().size()));
  if (!mechanism.home_actuators(mechanism_params, home_q).ok()) return "";
  int lengths = 0, short_ones = 0;
  double example_value = 0, example_home = 0;
  std::string example;
  for (int a = 0; a < home_q.size(); ++a) {
    if (mechanism.actuators()[a].unit != kMillimetre || !(std::abs(home_q[a]) > 0)) continue;
    std::vector<double> magnitudes;
    for (int row = 0; row < data.size(); ++row)
      if (std::isfinite(data.actuators(row, a)))
        magnitudes.push_back(std::abs(data.actuators(row, a)));
    if (magnitudes.empty()) continue;
    std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                     magnitudes.end());
    const double median = magnitudes[magnitudes.size() / 2];
    ++lengths;
    if (median < 0.25 * std::abs(home_q[a])) {
      ++short_ones;
      if (example.empty()) {
        example = mechanism.actuators()[a].name;
        example_value = median;
        example_home = home_q[a];
      }
    }
  }
  if (lengths == 0 || 2 * short_ones <= lengths) return "";
  return "the actuator values look like encoder strokes, not lengths (median |" + example +
         "| is " + format("%.4g", example_value) + " mm, while the model's " + example + " is " +
         format("%.4g", example_home) +
         " mm long at home): the model reads a length as value + offset, so set each "
         "actuator's offset in the model file to its length at the encoder's zero (measure it "
         "once, or compute it with kincal ik at a known pose), then free the offsets to refine "
         "them (e.g. --free '" +
         example + ".offset')";
}

}  // namespace kincal
