#pragma once
// Starting values for a camera's mounts without guesses, and the per-view cross-check of a
// calibrated camera: the target's pose in each view from its detected points alone (a
// perspective-n-point solution for a planar target: the homography of the undistorted points,
// decomposed, then refined on the pixels), and the closed-form hand-eye solution
// (framework/kinematics/hand_eye.hpp) of those poses against the mechanism's end-effector
// poses. The intrinsics are taken as they are in the parameters given: the user's values or
// OpenCV's calibration (`kincal detect --start-model`).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/analysis/image_views.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/kinematics/hand_eye.hpp"
#include "kincal/models/camera.hpp"

namespace kincal {

/// The target's pose in one view.
struct ViewPose {
  bool ok = false;
  Pose target_in_camera;  ///< x_camera = R x_target + t (mm)
  int points = 0;         ///< points detected in the view
  double rms_px = 0;      ///< reprojection error of the fitted pose
  std::string reason;     ///< why there is no pose, when !ok
};

/// The pose of `camera`'s target in its frame from one row of its readings (2 per point,
/// NaN for a point not detected) with the intrinsics of `camera_params` (the camera's own
/// slice of the parameters). Needs a planar target (every point with z = 0) and at least 4
/// points not on one line.
ViewPose solve_view_pose(const Camera& camera, const Eigen::Ref<const VectorXd>& camera_params,
                         const Eigen::Ref<const VectorXd>& reading);

/// The camera's mounts from every view: the frame parameters to give `<camera>.frame.*` and
/// `<camera>.target.*`.
struct CameraMountStart {
  bool ok = false;
  std::string reason;
  Vector6d frame = Vector6d::Zero(), target = Vector6d::Zero();
  std::vector<ViewPose> views;  ///< one per row of the data
  HandEyeSolution hand_eye;
  int views_used = 0;
};

/// Solves the mounts of the camera that is `sensor_index` of `model` from `data`, the
/// mechanism's poses computed with `params` (every parameter's value) and the intrinsics in
/// them. Fails (ok false, with the reason) with fewer than 3 views that have a pose, or when
/// the end effector's rotations between the views do not determine the mounts.
CameraMountStart estimate_camera_mounts(const MeasurementModel& model, int sensor_index,
                                        const Eigen::Ref<const VectorXd>& params,
                                        const Measurements& data);

/// What the calibrated model says of a view against what the view alone says: the target's
/// pose in the camera from the model (the mechanism's pose and both mounts) and from the
/// view's points (solve_view_pose, the calibrated intrinsics), and how far apart they are.
struct ViewCheck {
  int row = 0;          ///< row of the data (0-based)
  bool ok = false;      ///< both poses known
  std::string reason;   ///< why not, when !ok
  double position = 0;  ///< |t_model - t_view| (mm)
  double angle = 0;     ///< the angle of R_model^T R_view (rad)
};

/// One check per row of `data` for the camera that is `sensor_index` of `model` at `params`.
std::vector<ViewCheck> check_views(const MeasurementModel& model, int sensor_index,
                                   const Eigen::Ref<const VectorXd>& params,
                                   const Measurements& data);

/// The views that disagree with the calibrated model: a view whose position difference is
/// more than 3 times the median of all views' and more than 1 mm, or whose angle is more than 3
/// times the median and more than 1 mrad (a detection ordered wrongly, a pose row from another
/// image, a knocked target).
std::vector<int> disagreeing_views(const std::vector<ViewCheck>& checks);

/// The check in words for a report: the median and largest differences, then each view that
/// disagrees named by `labels` (one per row of the data, e.g. "D.csv:12").
std::string view_checks_text(const std::string& camera, const std::vector<ViewCheck>& checks,
                             const std::vector<std::string>& labels);

/// The same as JSON: {"camera", "views": [{"label", "ok", "position_mm", "angle_rad",
/// "reason"}], "disagreeing": [labels]}.
nlohmann::ordered_json view_checks_json(const std::string& camera,
                                        const std::vector<ViewCheck>& checks,
                                        const std::vector<std::string>& labels);

/// Every camera of `model` view by view at `params`: its reprojection error
/// (camera_image_views, models/camera_views.hpp) and each view's pose checked (check_views),
/// in words, as the JSON arrays a calibration report holds under "camera_views" and
/// "view_checks", and as the views the page for people draws; all empty without a camera.
/// `labels` name the rows (e.g. "D.csv:12"; empty: row numbers from 1), `images` the image
/// of each row when known (the measurement file's `image` column; may be empty).
struct CameraViewChecks {
  std::string text;
  nlohmann::ordered_json json = nlohmann::ordered_json::array();        ///< "view_checks"
  nlohmann::ordered_json views_json = nlohmann::ordered_json::array();  ///< "camera_views"
  std::vector<ImageViews> views;
};
CameraViewChecks camera_view_checks(const MeasurementModel& model,
                                    const Eigen::Ref<const VectorXd>& params,
                                    const Measurements& data, std::vector<std::string> labels,
                                    const std::vector<std::string>& images = {});

}  // namespace kincal
