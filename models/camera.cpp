#include "kincal/models/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace kincal {

namespace {

constexpr const char* kOne = "one";  // the unit of dimensionless numbers (units.cpp)

// Where the target's points are seen from: the camera's frame C and the target's frame T as
// the model's values give them, and the rotation that takes a vector in T's parent's axes
// into the camera's (the end effector's for eye-to-hand, the base's for eye-in-hand).
struct Placement {
  FrameBlock camera, target;
  Matrix3d camera_from_target_parent;
};

Placement placement(CameraMounting mounting, const Eigen::Ref<const VectorXd>& params,
                    const Pose& pose) {
  Placement p{frame_block(params.segment<6>(Camera::kFrameIndex)),
              frame_block(params.segment<6>(Camera::kTargetIndex)), Matrix3d()};
  const Matrix3d camera_from_parent = p.camera.frame.rotation.transpose();
  p.camera_from_target_parent = mounting == CameraMounting::kEyeToHand
                                    ? Matrix3d(camera_from_parent * pose.rotation)
                                    : Matrix3d(camera_from_parent * pose.rotation.transpose());
  return p;
}

// A target point `q` (in the target's parent's coordinates) in the camera's frame.
Vector3d in_camera(CameraMounting mounting, const Placement& p, const Pose& pose,
                   const Vector3d& q) {
  const Matrix3d camera_from_parent = p.camera.frame.rotation.transpose();
  if (mounting == CameraMounting::kEyeToHand)
    return camera_from_parent * (pose.rotation * q + pose.translation - p.camera.frame.translation);
  return camera_from_parent *
         (pose.rotation.transpose() * (q - pose.translation) - p.camera.frame.translation);
}

}  // namespace

const char* mounting_name(CameraMounting mounting) {
  return mounting == CameraMounting::kEyeToHand ? "eye-to-hand" : "eye-in-hand";
}

CameraTarget CameraTarget::grid(int rows, int columns, double spacing) {
  if (rows < 2 || columns < 2)
    throw std::invalid_argument("a grid target needs at least 2 rows and 2 columns, got " +
                                std::to_string(rows) + " x " + std::to_string(columns));
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw std::invalid_argument("a grid target's spacing must be finite and > 0");
  CameraTarget target;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      target.points.emplace_back(c * spacing, r * spacing, 0.0);
      target.names.push_back("p" + std::to_string(r * columns + c));
    }
  target.rows = rows;
  target.columns = columns;
  target.spacing = spacing;
  return target;
}

CameraTarget CameraTarget::from_points(std::vector<Vector3d> points) {
  if (points.size() < 4)
    throw std::invalid_argument("a target needs at least 4 points, got " +
                                std::to_string(points.size()));
  CameraTarget target;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw std::invalid_argument("target point " + std::to_string(i) + " is not finite");
    target.names.push_back("p" + std::to_string(i));
  }
  target.points = std::move(points);
  return target;
}

Camera::Camera(std::string name, CameraMounting mounting, CameraTarget target,
               const Vector6d& frame, const Vector6d& target_frame,
               const CameraIntrinsics& intrinsics, double image_width, double image_height)
    : name_(std::move(name)),
      mounting_(mounting),
      target_(std::move(target)),
      image_width_(image_width),
      image_height_(image_height),
      target_normal_(Vector3d::Zero()) {
  if (target_.points.empty() || target_.points.size() != target_.names.size())
    throw std::invalid_argument("camera '" + name_ + "': a target needs points, one name each");
  if (!(image_width > 0) || !(image_height > 0) || !std::isfinite(image_width) ||
      !std::isfinite(image_height))
    throw std::invalid_argument("camera '" + name_ + "': the image's size must be finite and > 0");
  bool planar = true;
  for (const Vector3d& p : target_.points) planar = planar && p.z() == 0;
  if (planar) target_normal_ = Vector3d::UnitZ();

  const char* suffixes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (int k = 0; k < 6; ++k)
    parameters_.push_back({name_ + ".frame." + suffixes[k], frame[k], k < 3 ? "mm" : "rad", false});
  for (int k = 0; k < 6; ++k)
    parameters_.push_back(
        {name_ + ".target." + suffixes[k], target_frame[k], k < 3 ? "mm" : "rad", false});
  const std::pair<const char*, double> pixels[4] = {
      {"fx", intrinsics.fx}, {"fy", intrinsics.fy}, {"cx", intrinsics.cx}, {"cy", intrinsics.cy}};
  for (const auto& [suffix, value] : pixels)
    parameters_.push_back({name_ + "." + suffix, value, kPixel, false});
  const std::pair<const char*, double> distortion[5] = {{"k1", intrinsics.k1},
                                                        {"k2", intrinsics.k2},
                                                        {"k3", intrinsics.k3},
                                                        {"p1", intrinsics.p1},
                                                        {"p2", intrinsics.p2}};
  for (const auto& [suffix, value] : distortion)
    parameters_.push_back({name_ + "." + suffix, value, kOne, false});
}

std::vector<std::string> Camera::reading_names() const {
  std::vector<std::string> names;
  names.reserve(2 * target_.names.size());
  for (const std::string& point : target_.names) {
    names.push_back(name_ + "." + point + ".u");
    names.push_back(name_ + "." + point + ".v");
  }
  return names;
}

bool Camera::valid_reading(int index, double value, std::string* reason) const {
  const bool is_u = index % 2 == 0;
  const double size = is_u ? image_width_ : image_height_;
  if (value >= -0.5 && value <= size - 0.5) return true;
  if (reason) {
    char text[160];
    std::snprintf(text, sizeof text, "%s = %g px is outside the image (%s %g px: %g to %g)",
                  is_u ? "u" : "v", value, is_u ? "width" : "height", size, -0.5, size - 0.5);
    *reason = text;
  }
  return false;
}

std::vector<std::string> Camera::reading_units() const {
  return std::vector<std::string>(static_cast<std::size_t>(num_readings()), kPixel);
}

void Camera::predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                     Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
                     MatrixXd* J_reading_params) const {
  const Placement p = placement(mounting_, params, pose);
  const Matrix3d camera_from_parent = p.camera.frame.rotation.transpose();
  const double* in = params.data() + kIntrinsicsIndex;
  const double fx = in[0], fy = in[1], cx = in[2], cy = in[3];
  const double k1 = in[4], k2 = in[5], k3 = in[6], p1 = in[7], p2 = in[8];
  // How a point in the camera's frame moves with the pose's [dt; dw]; the parts that do not
  // depend on the point.
  const Matrix3d camera_from_base = mounting_ == CameraMounting::kEyeToHand
                                        ? camera_from_parent
                                        : Matrix3d(camera_from_parent * pose.rotation.transpose());
  if (J_reading_params) J_reading_params->setZero();
  for (int i = 0; i < num_points(); ++i) {
    const Vector3d target_arm =
        p.target.frame.rotation * target_.points[static_cast<std::size_t>(i)];
    const Vector3d q = target_arm + p.target.frame.translation;  // in the target's parent's axes
    const Vector3d X = in_camera(mounting_, p, pose, q);
    const double iz = 1 / X.z();
    const double a = X.x() * iz, b = X.y() * iz;
    const double r2 = a * a + b * b;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double ad = a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a);
    const double bd = b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b;
    reading[2 * i] = fx * ad + cx;
    reading[2 * i + 1] = fy * bd + cy;
    if (!J_reading_pose && !J_reading_params) continue;

    // d(u, v) / dX: the distortion's 2x2 derivative in (a, b), then the perspective division.
    const double dradial = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // d radial / d r2
    Eigen::Matrix2d D;
    D << radial + 2 * a * a * dradial + 2 * p1 * b + 6 * p2 * a,
        2 * a * b * dradial + 2 * p1 * a + 2 * p2 * b,
        2 * a * b * dradial + 2 * p1 * a + 2 * p2 * b,
        radial + 2 * b * b * dradial + 6 * p1 * b + 2 * p2 * a;
    Eigen::Matrix<double, 2, 3> perspective;
    perspective << iz, 0, -a * iz, 0, iz, -b * iz;
    const Eigen::Matrix<double, 2, 3> P =
        Eigen::DiagonalMatrix<double, 2>(fx, fy) * D * perspective;

    if (J_reading_pose) {
      // Eye-to-hand: the point moves with the end effector, by dt + dw x (X_base - t).
      // Eye-in-hand: the camera moves; the point, fixed in the base, moves the other way in
      // the end effector's axes: -R^T dt + R^T [q - t]x dw.
      Eigen::Matrix<double, 3, 6> dX_pose;
      if (mounting_ == CameraMounting::kEyeToHand) {
        dX_pose.leftCols<3>() = camera_from_base;
        dX_pose.rightCols<3>() = -camera_from_base * skew(pose.rotation * q);
      } else {
        dX_pose.leftCols<3>() = -camera_from_base;
        dX_pose.rightCols<3>() = camera_from_base * skew(q - pose.translation);
      }
      J_reading_pose->middleRows<2>(2 * i) = P * dX_pose;
    }
    if (J_reading_params) {
      MatrixXd& J = *J_reading_params;
      // Moving the camera by dt moves what it sees by -dt; turning it by w turns what it sees
      // by -w about its origin (v = X in the camera's parent's axes, from its origin).
      const Vector3d v = p.camera.frame.rotation * X;
      J.block<2, 3>(2 * i, kFrameIndex) = -P * camera_from_parent;
      J.block<2, 3>(2 * i, kFrameIndex + 3) =
          P * camera_from_parent * skew(v) * p.camera.angular_jacobian;
      // The target's angles turn its points about its origin, in its parent's axes.
      J.block<2, 3>(2 * i, kTargetIndex) = P * p.camera_from_target_parent;
      J.block<2, 3>(2 * i, kTargetIndex + 3) =
          -P * p.camera_from_target_parent * skew(target_arm) * p.target.angular_jacobian;
      J(2 * i, kIntrinsicsIndex + 0) = ad;
      J(2 * i + 1, kIntrinsicsIndex + 1) = bd;
      J(2 * i, kIntrinsicsIndex + 2) = 1;
      J(2 * i + 1, kIntrinsicsIndex + 3) = 1;
      const double r4 = r2 * r2;
      J(2 * i, kIntrinsicsIndex + 4) = fx * a * r2;
      J(2 * i, kIntrinsicsIndex + 5) = fx * a * r4;
      J(2 * i, kIntrinsicsIndex + 6) = fx * a * r4 * r2;
      J(2 * i, kIntrinsicsIndex + 7) = fx * 2 * a * b;
      J(2 * i, kIntrinsicsIndex + 8) = fx * (r2 + 2 * a * a);
      J(2 * i + 1, kIntrinsicsIndex + 4) = fy * b * r2;
      J(2 * i + 1, kIntrinsicsIndex + 5) = fy * b * r4;
      J(2 * i + 1, kIntrinsicsIndex + 6) = fy * b * r4 * r2;
      J(2 * i + 1, kIntrinsicsIndex + 7) = fy * (r2 + 2 * b * b);
      J(2 * i + 1, kIntrinsicsIndex + 8) = fy * 2 * a * b;
    }
  }
}

bool Camera::reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                      std::string* reason) const {
  const Placement p = placement(mounting_, params, pose);
  for (const Vector3d& point : target_.points) {
    const Vector3d q = p.target.frame.rotation * point + p.target.frame.translation;
    if (!(in_camera(mounting_, p, pose, q).z() > 0)) {
      if (reason) *reason = "target behind the camera";
      return false;
    }
  }
  return true;
}

std::vector<bool> Camera::visible_points(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                         double max_tilt_rad) const {
  std::vector<bool> visible(target_.points.size(), false);
  VectorXd reading(num_readings());
  const bool in_front = reads_at(params, pose, nullptr);
  if (!in_front) return visible;
  predict(params, pose, reading, nullptr, nullptr);
  const Placement p = placement(mounting_, params, pose);
  const Vector3d normal = p.camera_from_target_parent * p.target.frame.rotation * target_normal_;
  const double min_cos = std::cos(max_tilt_rad);
  for (std::size_t i = 0; i < visible.size(); ++i) {
    const double u = reading[static_cast<Eigen::Index>(2 * i)];
    const double v = reading[static_cast<Eigen::Index>(2 * i + 1)];
    bool seen = u >= -0.5 && u <= image_width_ - 0.5 && v >= -0.5 && v <= image_height_ - 0.5;
    if (seen && target_normal_.squaredNorm() > 0) {
      const Vector3d q = p.target.frame.rotation * target_.points[i] + p.target.frame.translation;
      const Vector3d X = in_camera(mounting_, p, pose, q);
      seen = std::abs(normal.dot(X)) >= min_cos * X.norm();
    }
    visible[i] = seen;
  }
  return visible;
}

int Camera::drop_unseen(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                        Eigen::Ref<VectorXd> reading) const {
  std::vector<bool> visible = visible_points(params, pose, kMaxViewTilt);
  // A grid (chessboard, circle grid) is found whole or not at all, as OpenCV's detectors
  // find it; the points of any other target one by one.
  if (target_.rows > 0 && std::find(visible.begin(), visible.end(), false) != visible.end())
    visible.assign(visible.size(), false);
  int dropped = 0;
  for (std::size_t i = 0; i < visible.size(); ++i)
    if (!visible[i]) {
      reading.segment<2>(static_cast<Eigen::Index>(2 * i)).setConstant(NAN);
      dropped += 2;
    }
  return dropped;
}

}  // namespace kincal
