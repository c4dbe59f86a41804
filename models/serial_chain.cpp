#include "kincal/models/serial_chain.hpp"

#include <cstdio>

namespace kincal::serial_chain {

void add_frame_parameters(std::vector<Parameter>& out, const std::string& prefix,
                          const Vector6d& values) {
  static const char* const kSuffixes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    out.push_back({prefix + "." + kSuffixes[k], values[k], k < 3 ? "mm" : "rad", false});
}

Vector6d pose_error(const Pose& target, const Pose& current, double rotation_weight) {
  Vector6d e;
  e.head<3>() = target.translation - current.translation;
  e.tail<3>() = rotation_weight * log_so3(target.rotation * current.rotation.transpose());
  return e;
}

std::string pose_error_text(const Vector6d& e, double rotation_weight) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.3g mm and %.3g rad", e.head<3>().norm(),
                e.tail<3>().norm() / rotation_weight);
  return buf;
}

void describe_inverse_kinematics_failure(InverseKinematicsResult& result, const Vector6d& e,
                                         double rotation_weight, int joints, bool stationary) {
  const std::string size = pose_error_text(e, rotation_weight);
  if (stationary && joints < 6) {
    result.status = InverseKinematicsStatus::kUnreachable;
    result.reason = "the " + std::to_string(joints) + "-joint arm's closest pose is " + size +
                    " away (a least-squares minimum)";
  } else if (stationary) {
    result.status = InverseKinematicsStatus::kNotConverged;
    result.reason = "stopped at a stationary point " + size +
                    " from the pose: a local minimum, or the pose is out of reach";
  } else {
    result.status = InverseKinematicsStatus::kNotConverged;
    result.reason = "still " + size + " from the pose after " + std::to_string(result.iterations) +
                    " iterations";
  }
}

}  // namespace kincal::serial_chain
