#pragma once
// A camera seeing the points of a target: pinhole projection with Brown-Conrady lens
// distortion (OpenCV's model), two readings per target point, its pixel coordinates u, v.
//
// Mountings (where the camera and the target are):
//   eye-to-hand  the camera is fixed in the base frame (its frame parameters in base
//                coordinates) and the target is carried by the end effector (its frame in
//                end-effector coordinates);
//   eye-in-hand  the camera is carried by the end effector (its frame in end-effector
//                coordinates) and the target is fixed (its frame in base coordinates).
// A target point p (target coordinates) is X = (x, y, z) in the camera's frame (z along the
// optical axis, x to the right of the image, y down), then
//   a = x / z,  b = y / z,  r2 = a^2 + b^2,  radial = 1 + k1 r2 + k2 r2^2 + k3 r2^3
//   a' = a radial + 2 p1 a b + p2 (r2 + 2 a^2),  b' = b radial + p1 (r2 + 2 b^2) + 2 p2 a b
//   u = fx a' + cx,  v = fy b' + cy   (px; the image's top-left pixel's centre is 0, 0)
// Readings <name>.<point>.u and .v in px, <point> being the target's point names (p0, p1, ...
// in the order of the target's points: a grid's row by row, as OpenCV numbers chessboard
// corners). A point the camera did not detect is a missing reading (an empty field).
//
// Parameters: <name>.frame.{x, y, z, rx, ry, rz} (the camera, a frame block: pose.hpp),
// <name>.target.{x, y, z, rx, ry, rz} (the target), <name>.fx, .fy, .cx, .cy (px),
// <name>.k1, .k2, .k3, .p1, .p2 (the unit one: dimensionless).
//
// The camera reads a configuration only when every point of the target is in front of it
// (z > 0: a projection behind the camera means nothing); points in front but outside the
// image still project and are fitted when measured. Which points a camera would see (in front,
// inside the image, the target not seen edge-on) is visible_points(), for simulation and
// experiment design.

#include "kincal/framework/kinematics/sensor.hpp"

namespace kincal {

class ModelRegistry;

/// Where the camera and the target are mounted.
enum class CameraMounting {
  kEyeToHand,  ///< camera fixed in the base frame, target on the end effector
  kEyeInHand,  ///< camera on the end effector, target fixed in the base frame
};

/// "eye-to-hand" or "eye-in-hand".
const char* mounting_name(CameraMounting mounting);

/// The pinhole and distortion coefficients, in the order of the camera's parameters.
struct CameraIntrinsics {
  double fx = 1000, fy = 1000, cx = 640, cy = 512;  ///< px
  double k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0;    ///< OpenCV's (k1, k2, p1, p2, k3)
};

/// The points of a target in its own frame (mm) with their names.
struct CameraTarget {
  std::vector<Vector3d> points;
  std::vector<std::string> names;  ///< one per point: "p0", "p1", ...
  /// A planar grid: `rows` x `columns` points `spacing` apart (mm) in the target's x-y plane,
  /// point (r, c) at (c * spacing, r * spacing, 0), numbered row by row (chessboard inner
  /// corners, circle-grid centres). Throws std::invalid_argument for fewer than 2 rows or
  /// columns or a spacing that is not finite and positive.
  static CameraTarget grid(int rows, int columns, double spacing);
  /// Points as given, named p0, p1, ... Throws std::invalid_argument for fewer than 4 points
  /// or a point that is not finite.
  static CameraTarget from_points(std::vector<Vector3d> points);
  /// The grid's shape when made by grid() (for writing it back), else rows = 0.
  int rows = 0, columns = 0;
  double spacing = 0;
};

class Camera final : public Sensor {
 public:
  /// `frame`, `target_frame`: frame parameters [x, y, z, rx, ry, rz] (mm, rad;
  /// frame_from_parameters) of the camera and of the target, each in the coordinates the
  /// mounting says. `image_width`, `image_height`: the image's size in px (> 0). All
  /// parameters fixed (a model's mask frees them).
  Camera(std::string name, CameraMounting mounting, CameraTarget target, const Vector6d& frame,
         const Vector6d& target_frame, const CameraIntrinsics& intrinsics, double image_width,
         double image_height);

  std::string type() const override { return "camera"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 2 * num_points(); }
  std::vector<std::string> reading_names() const override;
  std::vector<std::string> reading_units() const override;
  const std::vector<Parameter>& parameters() const override { return parameters_; }

  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override;

  bool can_miss() const override { return true; }
  /// A camera-only fit can move a good robot to absorb the camera's errors (issue 38): priors
  /// from the stated tolerances by default.
  bool takes_tolerance_priors_by_default() const override { return true; }
  /// u and v of one point: each point detected or not.
  int reading_group_size() const override { return 2; }
  /// A pixel coordinate inside the image: -0.5 <= u <= width - 0.5 (v with the height), the
  /// edges of the outer pixels (pixel centres at 0 ... width - 1).
  bool valid_reading(int index, double value, std::string* reason) const override;
  /// False when a target point is not in front of the camera ("target behind the camera").
  bool reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                std::string* reason) const override;

  /// A simulated view: the points visible_points() does not see at kMaxViewTilt are missing;
  /// for a grid target every point is then missing (a chessboard or circle-grid detector
  /// finds the whole grid or nothing).
  int drop_unseen(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                  Eigen::Ref<VectorXd> reading) const override;
  /// The most a planar target may be turned from facing the camera and still be detected in a
  /// simulated view (60 degrees: a chessboard detector loses corners beyond about that).
  static constexpr double kMaxViewTilt = 1.0471975511965976;

  /// Per point, whether the camera would see it at `pose`: in front of the camera, inside the
  /// image, and the target's plane (for a planar target) turned less than `max_tilt_rad` from
  /// facing the camera. For simulation and experiment design; a calibration fits every
  /// measured point.
  std::vector<bool> visible_points(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                                   double max_tilt_rad) const;

  CameraMounting mounting() const { return mounting_; }
  const CameraTarget& target() const { return target_; }
  int num_points() const { return static_cast<int>(target_.points.size()); }
  double image_width() const { return image_width_; }
  double image_height() const { return image_height_; }

  static constexpr int kFrameIndex = 0;
  static constexpr int kTargetIndex = 6;
  static constexpr int kIntrinsicsIndex = 12;  ///< fx, fy, cx, cy, k1, k2, k3, p1, p2
  static constexpr int kNumParameters = 21;

 private:
  std::string name_;
  CameraMounting mounting_;
  CameraTarget target_;
  double image_width_, image_height_;
  Vector3d target_normal_;  ///< the target's plane normal (target frame), or 0 if not planar
  std::vector<Parameter> parameters_;
};

/// Registers the type (model-file reader/writer) and its presets.
void register_camera(ModelRegistry& registry);

}  // namespace kincal
