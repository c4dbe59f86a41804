#include "kincal/models/camera_start.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/models/camera_views.hpp"

namespace kincal {

namespace {

constexpr int kRefinementIterations = 50;

// The camera's intrinsics as a CameraIntrinsics.
CameraIntrinsics intrinsics_of(const Eigen::Ref<const VectorXd>& camera_params) {
  const double* in = camera_params.data() + Camera::kIntrinsicsIndex;
  CameraIntrinsics intrinsics;
  intrinsics.fx = in[0];
  intrinsics.fy = in[1];
  intrinsics.cx = in[2];
  intrinsics.cy = in[3];
  intrinsics.k1 = in[4];
  intrinsics.k2 = in[5];
  intrinsics.k3 = in[6];
  intrinsics.p1 = in[7];
  intrinsics.p2 = in[8];
  return intrinsics;
}

// The normalised image point (x / z, y / z) that projects to pixel (u, v): the distortion
// undone by fixed-point iteration from the distorted point, as OpenCV's undistortPoints.
Eigen::Vector2d undistort(const CameraIntrinsics& in, double u, double v) {
  const double a0 = (u - in.cx) / in.fx, b0 = (v - in.cy) / in.fy;
  double a = a0, b = b0;
  for (int i = 0; i < 20; ++i) {
    const double r2 = a * a + b * b;
    const double radial = 1 + r2 * (in.k1 + r2 * (in.k2 + r2 * in.k3));
    const double da = 2 * in.p1 * a * b + in.p2 * (r2 + 2 * a * a);
    const double db = in.p1 * (r2 + 2 * b * b) + 2 * in.p2 * a * b;
    a = (a0 - da) / radial;
    b = (b0 - db) / radial;
  }
  return {a, b};
}

// A similarity taking `points` to centroid 0 and mean distance sqrt(2) (Hartley's
// normalisation, which makes the homography's linear system well conditioned).
Matrix3d normalising_transform(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  double mean_distance = 0;
  for (const auto& p : points) mean_distance += (p - centroid).norm();
  mean_distance /= static_cast<double>(points.size());
  const double s = mean_distance > 0 ? std::sqrt(2.0) / mean_distance : 1;
  Matrix3d T;
  T << s, 0, -s * centroid.x(), 0, s, -s * centroid.y(), 0, 0, 1;
  return T;
}

// The homography H with image ~ H [X, Y, 1] by the normalised direct linear transform.
Matrix3d homography(const std::vector<Eigen::Vector2d>& plane,
                    const std::vector<Eigen::Vector2d>& image) {
  const Matrix3d Tp = normalising_transform(plane), Ti = normalising_transform(image);
  Eigen::Matrix<double, 9, 9> normal = Eigen::Matrix<double, 9, 9>::Zero();
  for (std::size_t k = 0; k < plane.size(); ++k) {
    const Vector3d p = Tp * Vector3d(plane[k].x(), plane[k].y(), 1);
    const Vector3d q = Ti * Vector3d(image[k].x(), image[k].y(), 1);
    Eigen::Matrix<double, 1, 9> row1, row2;
    row1 << p.transpose(), 0, 0, 0, -q.x() * p.transpose();
    row2 << 0, 0, 0, p.transpose(), -q.y() * p.transpose();
    normal += row1.transpose() * row1 + row2.transpose() * row2;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eigen(normal);
  const Eigen::Matrix<double, 9, 1> h = eigen.eigenvectors().col(0);
  Matrix3d Hn;
  Hn << h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8];
  return Ti.inverse() * Hn * Tp;
}

// The nearest rotation to M (Frobenius norm).
Matrix3d nearest_rotation(const Matrix3d& M) {
  const Eigen::JacobiSVD<Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3d U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) = -U.col(2);
  return U * svd.matrixV().transpose();
}

// The mean of poses: the rotation nearest the sum of rotations, the mean translation.
Pose mean_pose(const std::vector<Pose>& poses) {
  Matrix3d sum = Matrix3d::Zero();
  Vector3d translation = Vector3d::Zero();
  for (const Pose& p : poses) {
    sum += p.rotation;
    translation += p.translation;
  }
  Pose mean;
  mean.rotation = nearest_rotation(sum);
  mean.translation = translation / static_cast<double>(poses.size());
  return mean;
}

}  // namespace

ViewPose solve_view_pose(const Camera& camera, const Eigen::Ref<const VectorXd>& camera_params,
                         const Eigen::Ref<const VectorXd>& reading) {
  ViewPose view;
  const CameraTarget& target = camera.target();
  for (const Vector3d& p : target.points)
    if (p.z() != 0) {
      view.reason = "the target is not planar (a starting pose needs its points at z = 0)";
      return view;
    }
  const CameraIntrinsics in = intrinsics_of(camera_params);
  std::vector<Eigen::Vector2d> plane, image;
  std::vector<int> present;
  for (int i = 0; i < camera.num_points(); ++i) {
    const double u = reading[2 * i], v = reading[2 * i + 1];
    if (!std::isfinite(u) || !std::isfinite(v)) continue;
    present.push_back(i);
    plane.emplace_back(target.points[static_cast<std::size_t>(i)].head<2>());
    image.push_back(undistort(in, u, v));
  }
  view.points = static_cast<int>(present.size());
  if (view.points < 4) {
    view.reason = std::to_string(view.points) + " points detected (a pose needs 4)";
    return view;
  }
  // The points must span the plane, not a line.
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : plane) centroid += p;
  centroid /= static_cast<double>(plane.size());
  for (const auto& p : plane) spread += (p - centroid) * (p - centroid).transpose();
  const Eigen::Vector2d extent =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(spread).eigenvalues();
  if (!(extent[0] > 1e-6 * extent[1])) {
    view.reason = "the detected points lie on one line";
    return view;
  }

  // Zhang's decomposition of H = [r1 r2 t] up to scale, in normalised image coordinates.
  const Matrix3d H = homography(plane, image);
  double scale = 2 / (H.col(0).norm() + H.col(1).norm());
  if (H(2, 2) * scale < 0) scale = -scale;  // the target in front of the camera
  Matrix3d R;
  R.col(0) = scale * H.col(0);
  R.col(1) = scale * H.col(1);
  R.col(2) = R.col(0).cross(R.col(1));
  Pose pose;
  pose.rotation = nearest_rotation(R);
  pose.translation = scale * H.col(2);
  if (!pose.rotation.allFinite() || !pose.translation.allFinite()) {
    view.reason = "the points give no homography";
    return view;
  }

  // Refined on the pixels, distortion included, by damped Gauss-Newton: the target seen by a
  // camera at the origin (frame and target mounts zero) is the pose itself.
  const Camera at_origin("view", CameraMounting::kEyeToHand, target, Vector6d::Zero(),
                         Vector6d::Zero(), in, camera.image_width(), camera.image_height());
  VectorXd params = VectorXd::Zero(Camera::kNumParameters);
  params.tail<9>() = camera_params.segment<9>(Camera::kIntrinsicsIndex);
  const int n = camera.num_readings();
  VectorXd predicted(n);
  MatrixXd J(n, 6);
  auto cost_at = [&](const Pose& p, Matrix6d* normal, Vector6d* gradient) {
    at_origin.predict(params, p, predicted, normal ? &J : nullptr, nullptr);
    double cost = 0;
    if (normal) {
      normal->setZero();
      gradient->setZero();
    }
    for (int i : present)
      for (int k = 2 * i; k < 2 * i + 2; ++k) {
        const double r = predicted[k] - reading[k];
        cost += r * r;
        if (normal) {
          *normal += J.row(k).transpose() * J.row(k);
          *gradient += J.row(k).transpose() * r;
        }
      }
    return cost;
  };
  Matrix6d normal;
  Vector6d gradient;
  double cost = cost_at(pose, &normal, &gradient);
  double damping = 1e-3;
  for (int iteration = 0; iteration < kRefinementIterations && std::isfinite(cost); ++iteration) {
    Matrix6d damped = normal;
    damped.diagonal() *= 1 + damping;
    const Vector6d step = -damped.ldlt().solve(gradient);
    const Pose trial = perturb(pose, step);
    const double trial_cost = cost_at(trial, nullptr, nullptr);
    if (std::isfinite(trial_cost) && trial_cost <= cost) {
      const bool small = cost - trial_cost <= 1e-12 * cost;
      pose = trial;
      cost = cost_at(pose, &normal, &gradient);
      damping = std::max(damping / 10, 1e-9);
      if (small) break;
    } else {
      damping *= 10;
      if (damping > 1e8) break;
    }
  }
  if (!std::isfinite(cost) || pose.translation.z() <= 0) {
    view.reason = "no pose puts the target in front of the camera";
    return view;
  }
  view.ok = true;
  view.target_in_camera = pose;
  view.rms_px = std::sqrt(cost / (2.0 * view.points));
  return view;
}

namespace {

const Camera& camera_of(const MeasurementModel& model, int sensor_index) {
  if (sensor_index < 0 || sensor_index >= static_cast<int>(model.sensors().size()))
    throw std::invalid_argument("no sensor " + std::to_string(sensor_index) + " in the model");
  const auto* camera = dynamic_cast<const Camera*>(model.sensors()[sensor_index].get());
  if (!camera)
    throw std::invalid_argument("sensor '" + model.sensors()[sensor_index]->name() +
                                "' is not a camera");
  return *camera;
}

// The end effector's pose at each row (ok false where forward kinematics fails).
struct RowPose {
  bool ok = false;
  Pose pose;
};
RowPose end_effector_pose(const MeasurementModel& model, const Eigen::Ref<const VectorXd>& params,
                          const Measurements& data, int row) {
  const Mechanism& mechanism = model.mechanism();
  const auto result =
      mechanism.forward_kinematics(params.head(mechanism.num_parameters()),
                                   data.actuators.row(row).transpose(), mechanism.home_pose());
  return {result.ok(), result.pose};
}

}  // namespace

CameraMountStart estimate_camera_mounts(const MeasurementModel& model, int sensor_index,
                                        const Eigen::Ref<const VectorXd>& params,
                                        const Measurements& data) {
  const Camera& camera = camera_of(model, sensor_index);
  const VectorXd camera_params =
      params.segment(model.sensor_parameter_offset(sensor_index), camera.num_parameters());
  const int reading_offset = model.sensor_reading_offset(sensor_index);
  CameraMountStart start;
  std::vector<Pose> flanges, views;
  for (int row = 0; row < data.size(); ++row) {
    start.views.push_back(solve_view_pose(
        camera, camera_params,
        data.readings.row(row).segment(reading_offset, camera.num_readings()).transpose()));
    const RowPose flange = end_effector_pose(model, params, data, row);
    if (!start.views.back().ok || !flange.ok) continue;
    flanges.push_back(flange.pose);
    views.push_back(start.views.back().target_in_camera);
  }
  start.views_used = static_cast<int>(views.size());
  if (start.views_used < 3) {
    start.reason =
        std::to_string(start.views_used) + " views with a target pose (the mounts need 3 or more)";
    return start;
  }
  // Every pair of views is a motion: A the end effector's, B the target's as the camera saw
  // it, X the mount on the end effector (eye-to-hand: the target's; eye-in-hand: the
  // camera's).
  const bool eye_to_hand = camera.mounting() == CameraMounting::kEyeToHand;
  std::vector<Pose> A, B;
  for (std::size_t i = 0; i < views.size(); ++i)
    for (std::size_t j = i + 1; j < views.size(); ++j) {
      A.push_back(compose(inverse(flanges[j]), flanges[i]));
      B.push_back(eye_to_hand ? compose(inverse(views[j]), views[i])
                              : compose(views[j], inverse(views[i])));
    }
  start.hand_eye = solve_hand_eye(A, B);
  if (!start.hand_eye.ok) {
    start.reason = start.hand_eye.reason;
    return start;
  }
  const Pose& X = start.hand_eye.X;
  // The other mount, from each view, averaged.
  std::vector<Pose> others;
  for (std::size_t i = 0; i < views.size(); ++i)
    others.push_back(eye_to_hand ? compose(compose(flanges[i], X), inverse(views[i]))
                                 : compose(compose(flanges[i], X), views[i]));
  const Pose other = mean_pose(others);
  start.frame = frame_parameters(eye_to_hand ? other : X);
  start.target = frame_parameters(eye_to_hand ? X : other);
  start.ok = true;
  return start;
}

std::vector<ViewCheck> check_views(const MeasurementModel& model, int sensor_index,
                                   const Eigen::Ref<const VectorXd>& params,
                                   const Measurements& data) {
  const Camera& camera = camera_of(model, sensor_index);
  const VectorXd camera_params =
      params.segment(model.sensor_parameter_offset(sensor_index), camera.num_parameters());
  const Pose camera_frame = frame_from_parameters(camera_params.segment<6>(Camera::kFrameIndex));
  const Pose target_frame = frame_from_parameters(camera_params.segment<6>(Camera::kTargetIndex));
  const int reading_offset = model.sensor_reading_offset(sensor_index);
  std::vector<ViewCheck> checks;
  for (int row = 0; row < data.size(); ++row) {
    ViewCheck check;
    check.row = row;
    const ViewPose view = solve_view_pose(
        camera, camera_params,
        data.readings.row(row).segment(reading_offset, camera.num_readings()).transpose());
    const RowPose flange = end_effector_pose(model, params, data, row);
    if (!view.ok) {
      check.reason = view.reason;
    } else if (!flange.ok) {
      check.reason = "forward kinematics fails";
    } else {
      const Pose predicted =
          camera.mounting() == CameraMounting::kEyeToHand
              ? compose(inverse(camera_frame), compose(flange.pose, target_frame))
              : compose(inverse(camera_frame), compose(inverse(flange.pose), target_frame));
      check.ok = true;
      check.position = (predicted.translation - view.target_in_camera.translation).norm();
      check.angle = log_so3(predicted.rotation.transpose() * view.target_in_camera.rotation).norm();
    }
    checks.push_back(check);
  }
  return checks;
}

namespace {

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

std::vector<int> disagreeing_views(const std::vector<ViewCheck>& checks) {
  std::vector<double> positions, angles;
  for (const ViewCheck& c : checks)
    if (c.ok) {
      positions.push_back(c.position);
      angles.push_back(c.angle);
    }
  const double position_limit = std::max(1.0, 3 * median(positions));
  const double angle_limit = std::max(1e-3, 3 * median(angles));
  std::vector<int> out;
  for (std::size_t k = 0; k < checks.size(); ++k)
    if (checks[k].ok && (checks[k].position > position_limit || checks[k].angle > angle_limit))
      out.push_back(static_cast<int>(k));
  return out;
}

std::string view_checks_text(const std::string& camera, const std::vector<ViewCheck>& checks,
                             const std::vector<std::string>& labels) {
  std::vector<double> positions, angles;
  int without = 0;
  for (const ViewCheck& c : checks) {
    if (!c.ok) {
      ++without;
      continue;
    }
    positions.push_back(c.position);
    angles.push_back(c.angle);
  }
  std::string text = "views of " + camera + " against their own poses (each view's points alone, ";
  if (positions.empty()) return text + "the calibrated intrinsics): none has a pose\n";
  text += format_text(
      "the calibrated intrinsics): median %.3g mm / %.3g mrad apart, largest %.3g mm / %.3g "
      "mrad",
      median(positions), 1e3 * median(angles),
      *std::max_element(positions.begin(), positions.end()),
      1e3 * *std::max_element(angles.begin(), angles.end()));
  if (without) text += format_text("; %d without a pose", without);
  text += "\n";
  for (int k : disagreeing_views(checks))
    text += format_text(
        "  %s disagrees: %.3g mm, %.3g mrad from the model's pose of the target "
        "(a wrongly ordered detection, a pose row from another image, a moved "
        "target?)\n",
        labels[static_cast<std::size_t>(k)].c_str(), checks[static_cast<std::size_t>(k)].position,
        1e3 * checks[static_cast<std::size_t>(k)].angle);
  return text;
}

nlohmann::ordered_json view_checks_json(const std::string& camera,
                                        const std::vector<ViewCheck>& checks,
                                        const std::vector<std::string>& labels) {
  nlohmann::ordered_json out;
  out["camera"] = camera;
  out["views"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < checks.size(); ++k) {
    nlohmann::ordered_json v{{"label", labels[k]}, {"ok", checks[k].ok}};
    if (checks[k].ok) {
      v["position_mm"] = checks[k].position;
      v["angle_rad"] = checks[k].angle;
    } else {
      v["reason"] = checks[k].reason;
    }
    out["views"].push_back(v);
  }
  out["disagreeing"] = nlohmann::ordered_json::array();
  for (int k : disagreeing_views(checks))
    out["disagreeing"].push_back(labels[static_cast<std::size_t>(k)]);
  return out;
}

CameraViewChecks camera_view_checks(const MeasurementModel& model,
                                    const Eigen::Ref<const VectorXd>& params,
                                    const Measurements& data, std::vector<std::string> labels,
                                    const std::vector<std::string>& images) {
  for (int k = static_cast<int>(labels.size()); k < data.size(); ++k)
    labels.push_back("row " + std::to_string(k + 1));
  CameraViewChecks out;
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    if (!dynamic_cast<const Camera*>(model.sensors()[s].get())) continue;
    out.views.push_back(
        camera_image_views(model, static_cast<int>(s), params, data, labels, images));
    out.text += image_views_text(out.views.back());
    out.views_json.push_back(image_views_json(out.views.back()));
    const auto checks = check_views(model, static_cast<int>(s), params, data);
    const std::string& name = model.sensors()[s]->name();
    out.text += view_checks_text(name, checks, labels);
    out.json.push_back(view_checks_json(name, checks, labels));
  }
  return out;
}

}  // namespace kincal
