// The camera in model files, and its presets. A camera's object:
//   { "type": "camera", "name": "camera", "mounting": "eye-to-hand",
//     "image": { "width": 1280, "height": 1024 },                          (px)
//     "frame": { "position": [x, y, z], "rotation_zyx_deg": [rx, ry, rz] },
//     "target": { "frame": { "position": ..., "rotation_zyx_deg": ... },
//                 "grid": { "rows": 6, "columns": 8, "spacing": 20 } },    (or "points")
//     "intrinsics": { "fx": 1200, "fy": 1200, "cx": 640, "cy": 512 },       (px)
//     "distortion": { "k1": 0, "k2": 0, "k3": 0, "p1": 0, "p2": 0 } }    (optional; 0)
// "frame" is the camera's frame (z along the optical axis, x to the image's right, y down),
// "target.frame" the target's; each in base coordinates when fixed, in the end effector's
// when carried (models/camera.hpp). "points": [[x, y, z], ...] (mm, at least 4) instead of
// "grid" for any other target.
//
// Presets: ur5-urdf-camera (eye-to-hand: a camera on a tripod, a chessboard on a bracket at
// the flange), ur5-urdf-eye-in-hand (a camera on the flange, a chessboard on the table) and
// cube-hexapod-camera (a camera above the paper's hexapod, a chessboard on its platform).

#include <cmath>

#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/io/json_fields.hpp"
#include "kincal/models/camera.hpp"
#include "kincal/models/flange_pose.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/urdf_arm.hpp"

namespace kincal {

namespace {

CameraMounting read_mounting(const Json& value, const JsonPath& where) {
  const std::string text = json_field::string(value, where);
  if (text == "eye-to-hand") return CameraMounting::kEyeToHand;
  if (text == "eye-in-hand") return CameraMounting::kEyeInHand;
  where.fail(
      "expected \"eye-to-hand\" (camera fixed, target on the end effector) or "
      "\"eye-in-hand\" (camera on the end effector, target fixed), got \"" +
      text + "\"");
}

int read_count(const Json& object, const std::string& key, const JsonPath& where) {
  const double value = json_field::number(json_field::member(object, key, where), where / key);
  if (value != std::floor(value) || value < 2 || value > 1000)
    (where / key).fail("expected a whole number from 2 to 1000");
  return static_cast<int>(value);
}

CameraTarget read_target_points(const Json& target, const JsonPath& where) {
  const Json* grid = json_field::optional(target, "grid");
  const Json* points = json_field::optional(target, "points");
  if ((grid != nullptr) == (points != nullptr))
    where.fail("expected either \"grid\" (rows, columns, spacing) or \"points\"");
  try {
    if (grid) {
      const JsonPath at = where / "grid";
      json_field::object(*grid, at);
      json_field::check_keys(*grid, at, {"rows", "columns", "spacing"});
      const double spacing =
          json_field::number(json_field::member(*grid, "spacing", at), at / "spacing");
      return CameraTarget::grid(read_count(*grid, "rows", at), read_count(*grid, "columns", at),
                                spacing);
    }
    const JsonPath at = where / "points";
    if (!points->is_array()) at.fail("expected an array of points [x, y, z] (mm)");
    std::vector<Vector3d> xyz;
    for (std::size_t i = 0; i < points->size(); ++i)
      xyz.push_back(json_field::vector3((*points)[i], at[i]));
    return CameraTarget::from_points(std::move(xyz));
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind(where.source(), 0) == 0) throw;  // already located
    where.fail(what);
  }
}

std::shared_ptr<const Sensor> read_camera(const Json& object, const JsonPath& where) {
  json_field::check_keys(
      object, where,
      {"type", "name", "mounting", "image", "frame", "target", "intrinsics", "distortion"});
  const std::string name =
      json_field::name(json_field::member(object, "name", where), where / "name");
  const CameraMounting mounting =
      read_mounting(json_field::member(object, "mounting", where), where / "mounting");

  const JsonPath image_at = where / "image";
  const Json& image = json_field::object(json_field::member(object, "image", where), image_at);
  json_field::check_keys(image, image_at, {"width", "height"});
  double size[2];
  const char* size_keys[2] = {"width", "height"};
  for (int k = 0; k < 2; ++k) {
    size[k] = json_field::number(json_field::member(image, size_keys[k], image_at),
                                 image_at / size_keys[k]);
    if (!(size[k] >= 1) || size[k] > 1e6)
      (image_at / size_keys[k]).fail("expected px from 1 to 1e6");
  }

  const Vector6d frame =
      json_field::frame(json_field::member(object, "frame", where), where / "frame");
  const JsonPath target_at = where / "target";
  const Json& target = json_field::object(json_field::member(object, "target", where), target_at);
  json_field::check_keys(target, target_at, {"frame", "grid", "points"});
  const Vector6d target_frame =
      json_field::frame(json_field::member(target, "frame", target_at), target_at / "frame");
  CameraTarget points = read_target_points(target, target_at);

  CameraIntrinsics in;
  const JsonPath intrinsics_at = where / "intrinsics";
  const Json& intrinsics =
      json_field::object(json_field::member(object, "intrinsics", where), intrinsics_at);
  json_field::check_keys(intrinsics, intrinsics_at, {"fx", "fy", "cx", "cy"});
  const std::pair<const char*, double*> pixels[4] = {
      {"fx", &in.fx}, {"fy", &in.fy}, {"cx", &in.cx}, {"cy", &in.cy}};
  for (const auto& [key, value] : pixels)
    *value =
        json_field::number(json_field::member(intrinsics, key, intrinsics_at), intrinsics_at / key);
  if (!(in.fx > 0) || !(in.fy > 0)) intrinsics_at.fail("expected focal lengths fx, fy > 0 (px)");
  if (const Json* distortion = json_field::optional(object, "distortion")) {
    const JsonPath at = where / "distortion";
    json_field::object(*distortion, at);
    json_field::check_keys(*distortion, at, {"k1", "k2", "k3", "p1", "p2"});
    const std::pair<const char*, double*> coefficients[5] = {
        {"k1", &in.k1}, {"k2", &in.k2}, {"k3", &in.k3}, {"p1", &in.p1}, {"p2", &in.p2}};
    for (const auto& [key, value] : coefficients)
      *value = json_field::number_or(*distortion, key, 0, at);
  }
  return std::make_shared<Camera>(name, mounting, std::move(points), frame, target_frame, in,
                                  size[0], size[1]);
}

Json write_camera(const Sensor& sensor, const Eigen::Ref<const VectorXd>& v) {
  const auto& camera = dynamic_cast<const Camera&>(sensor);
  Json target;
  target["frame"] = json_field::pose_json(Vector3d(v.segment<3>(Camera::kTargetIndex)),
                                          Vector3d(v.segment<3>(Camera::kTargetIndex + 3)));
  const CameraTarget& points = camera.target();
  if (points.rows > 0) {
    target["grid"] = {
        {"rows", points.rows}, {"columns", points.columns}, {"spacing", points.spacing}};
  } else {
    Json list = Json::array();
    for (const Vector3d& p : points.points) list.push_back(json_field::array3(p));
    target["points"] = list;
  }
  const int i = Camera::kIntrinsicsIndex;
  Json object = {
      {"name", camera.name()},
      {"mounting", mounting_name(camera.mounting())},
      {"image", {{"width", camera.image_width()}, {"height", camera.image_height()}}},
      {"frame", json_field::pose_json(Vector3d(v.segment<3>(Camera::kFrameIndex)),
                                      Vector3d(v.segment<3>(Camera::kFrameIndex + 3)))},
      {"target", target},
      {"intrinsics", {{"fx", v[i]}, {"fy", v[i + 1]}, {"cx", v[i + 2]}, {"cy", v[i + 3]}}},
      {"distortion",
       {{"k1", v[i + 4]}, {"k2", v[i + 5]}, {"k3", v[i + 6]}, {"p1", v[i + 7]}, {"p2", v[i + 8]}}}};
  return object;
}

// The camera's frame looking along `forward` from `position`, its x axis as near `right` as
// the view allows, as frame parameters.
Vector6d looking(const Vector3d& position, const Vector3d& forward, const Vector3d& right) {
  Pose frame;
  const Vector3d z = forward.normalized();
  const Vector3d x = (right - right.dot(z) * z).normalized();
  frame.rotation.col(0) = x;
  frame.rotation.col(1) = z.cross(x);
  frame.rotation.col(2) = z;
  frame.translation = position;
  return frame_parameters(frame);
}

// The UR5 preset's arm with a configuration box small enough for the target to stay in the
// camera's view (0.25 rad each way per joint).
std::shared_ptr<const UrdfArm> ur5_within_view() {
  const auto arm_model = make_ur5_urdf();
  UrdfArmGeometry geometry =
      dynamic_cast<const UrdfArm&>(arm_model->mechanism()).nominal_geometry();
  for (UrdfArmJoint& joint : geometry.joints) joint.range = 0.25;
  return std::make_shared<UrdfArm>(geometry);
}

// A chessboard of 6 x 8 inner corners 20 mm apart, and a 1280 x 1024 camera of 1200 px focal
// length (a 56-degree horizontal view) with a little barrel distortion.
constexpr int kRows = 6, kColumns = 8;
constexpr double kSpacing = 20;
CameraIntrinsics preset_intrinsics() {
  CameraIntrinsics in;
  in.fx = 1200;
  in.fy = 1200;
  in.cx = 640;
  in.cy = 512;
  in.k1 = -0.08;
  in.k2 = 0.05;
  return in;
}

// Errors a simulation draws for the intrinsics (px, and the distortion's unit one) and the
// camera's own mask: fx, fy, cx, cy, k1, k2, p1, p2 free; k3 fixed (it only matters near the
// image's corners).
void set_camera_errors_and_mask(MeasurementModel& model) {
  ParameterSet& parameters = model.parameters();
  const std::pair<const char*, double> errors[] = {{"camera.f?", 20},
                                                   {"camera.c?", 10},
                                                   {"camera.k1", 0.02},
                                                   {"camera.k2", 0.02},
                                                   {"camera.p?", 0.002}};
  for (const auto& error : errors) {
    const double half_width = error.second;  // a structured binding cannot be captured (C++17)
    parameters.for_each_matching(error.first,
                                 [half_width](Parameter& p) { p.error_half_width = half_width; });
  }
  for (const char* free : {"camera.f?", "camera.c?", "camera.k1", "camera.k2", "camera.p?"})
    parameters.set_free(free, true);
  parameters.set_free("camera.k3", false);
}

// The camera's mask, and the URDF arm's and mounts' parameters that the preset's views
// determine.
void free_camera_and_what_views_determine(MeasurementModel& model) {
  free_what_home_configurations_determine(model, 1.7, 2.3, 0.1);
  set_camera_errors_and_mask(model);
}

std::shared_ptr<MeasurementModel> make_ur5_urdf_camera() {
  const auto arm = ur5_within_view();
  const Pose flange = arm->home_pose();  // pointing down at home
  // The board on a bracket beside the flange, in the plane of the flange's x and z axes
  // (turned 90 degrees about x), its centre 40 mm off the axis and 60 mm out; it faces the
  // flange's -y, horizontal at home. The camera on a tripod 800 mm in front of it, level.
  const Vector3d board_centre((kColumns - 1) * kSpacing / 2, (kRows - 1) * kSpacing / 2, 0);
  Vector6d target_frame;
  target_frame << 0, 0, 0, kPi / 2, 0, 0;
  const Pose bracket = frame_from_parameters(target_frame);
  target_frame.head<3>() = Vector3d(0, -40, 60) - bracket.rotation * board_centre;
  const Vector3d centre = flange.translation + flange.rotation * Vector3d(0, -40, 60);
  const Vector3d facing = flange.rotation * bracket.rotation.col(2);
  const Vector3d forward = -facing;
  const Vector6d camera_frame =
      looking(centre + 800 * facing, forward, forward.cross(Vector3d::UnitZ()));
  auto camera = std::make_shared<Camera>(
      "camera", CameraMounting::kEyeToHand, CameraTarget::grid(kRows, kColumns, kSpacing),
      camera_frame, target_frame, preset_intrinsics(), 1280, 1024);
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{camera});
  free_camera_and_what_views_determine(*model);
  return model;
}

std::shared_ptr<MeasurementModel> make_ur5_urdf_eye_in_hand() {
  const auto arm = ur5_within_view();
  const Pose flange = arm->home_pose();
  const Vector3d out = flange.rotation.col(2);
  // The camera on the flange, 60 mm off its axis, looking out along it (down at home); the
  // board on the table 400 mm away on the camera's axis, facing it.
  Vector6d camera_frame;
  camera_frame << 0, 60, 30, 0, 0, 0;
  const Pose camera_in_base = compose(flange, frame_from_parameters(camera_frame));
  const Vector3d on_axis = camera_in_base.translation + 400 * out;
  Pose board;
  board.rotation = camera_in_base.rotation;  // facing the camera, rows along its image rows
  const Vector3d board_centre((kColumns - 1) * kSpacing / 2, (kRows - 1) * kSpacing / 2, 0);
  board.translation = on_axis - board.rotation * board_centre;
  auto camera = std::make_shared<Camera>(
      "camera", CameraMounting::kEyeInHand, CameraTarget::grid(kRows, kColumns, kSpacing),
      camera_frame, frame_parameters(board), preset_intrinsics(), 1280, 1024);
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{camera});
  free_camera_and_what_views_determine(*model);
  return model;
}

// The paper's cube hexapod seen from above: a camera 800 mm over the platform's home looking
// down at a 6 x 8 chessboard on the platform (eye-to-hand). The hexapod's free set is the
// paper's (cube-hexapod: legs 4-6 whole, z of legs 1-3); the camera's intrinsics, distortion
// but k3 and both mounts free.
std::shared_ptr<MeasurementModel> make_cube_hexapod_camera() {
  const auto hexapod = make_cube_hexapod();
  const Pose home = hexapod->mechanism().home_pose();
  const Vector3d board_centre((kColumns - 1) * kSpacing / 2, (kRows - 1) * kSpacing / 2, 0);
  Vector6d target_frame;
  target_frame << -board_centre.x(), -board_centre.y(), 5, 0, 0, 0;
  const Vector6d camera_frame =
      looking(home.translation + Vector3d(0, 0, 800), -Vector3d::UnitZ(), Vector3d::UnitX());
  auto camera = std::make_shared<Camera>(
      "camera", CameraMounting::kEyeToHand, CameraTarget::grid(kRows, kColumns, kSpacing),
      camera_frame, target_frame, preset_intrinsics(), 1280, 1024);
  auto model = std::make_shared<MeasurementModel>(
      hexapod->mechanism_ptr(), std::vector<std::shared_ptr<const Sensor>>{camera});
  for (int i : hexapod->parameters().free_indices())
    model->parameters().set_free(hexapod->parameters()[i].name, true);
  model->parameters().set_free("camera.frame.*", true);
  model->parameters().set_free("camera.target.*", true);
  set_camera_errors_and_mask(*model);
  // A camera sees the platform's whole pose, where the paper's gauge saw one length: of those
  // candidates, keep the ones 30 drawn views determine, the camera's own first (a shift of the
  // platform's frame along z is the board's distance from it, and so on).
  ScenarioOptions options;
  options.num_validation = 0;
  options.param_error_half_width = UnitValues();
  const Scenario views = make_scenario(std::make_shared<const MeasurementModel>(*model), options);
  const auto problem = views.make_problem();
  VectorXd residuals;
  MatrixXd J;
  std::string why;
  if (!problem->evaluate(problem->initial_free_parameters(), &residuals, &J, &why))
    throw std::logic_error("cube-hexapod-camera: the preset's views cannot be evaluated: " + why);
  std::vector<int> priority;
  for (int i : views.free_indices)
    priority.push_back(model->parameters()[i].name.rfind("camera.", 0) == 0 ? 0 : 1);
  const std::vector<int> keep = identifiable_subset(J, priority);
  for (int i : views.free_indices) model->parameters().set_free(model->parameters()[i].name, false);
  for (int k : keep)
    model->parameters().set_free(
        model->parameters()[views.free_indices[static_cast<std::size_t>(k)]].name, true);
  return model;
}

// A robot known by its reported flange poses (a hand-eye data set's: no joint angles)
// carrying a 10 x 10 circle grid 25.4 mm apart, 50 mm out from the flange, seen by a fixed
// 640 x 480 camera 700 mm away (ROS-Industrial's example cell): the camera's intrinsics and
// distortion but k3 and both mounts free, the flange poses taken as exact.
std::shared_ptr<MeasurementModel> make_flange_pose_camera() {
  constexpr int kGrid = 10;
  constexpr double kPitch = 25.4;
  const auto robot = std::make_shared<FlangePose>(Pose(), 100.0, 0.35);
  const Vector3d board_centre((kGrid - 1) * kPitch / 2, (kGrid - 1) * kPitch / 2, 0);
  Vector6d target_frame;
  target_frame << -board_centre.x(), -board_centre.y(), 50, 0, 0, 0;
  const Vector6d camera_frame = looking(Vector3d(0, 0, 750), -Vector3d::UnitZ(), Vector3d::UnitX());
  CameraIntrinsics intrinsics;
  intrinsics.fx = 550;
  intrinsics.fy = 550;
  intrinsics.cx = 320;
  intrinsics.cy = 240;
  intrinsics.k1 = -0.05;
  auto camera = std::make_shared<Camera>("camera", CameraMounting::kEyeToHand,
                                         CameraTarget::grid(kGrid, kGrid, kPitch), camera_frame,
                                         target_frame, intrinsics, 640, 480);
  auto model =
      std::make_shared<MeasurementModel>(robot, std::vector<std::shared_ptr<const Sensor>>{camera});
  model->parameters().set_free("camera.frame.*", true);
  model->parameters().set_free("camera.target.*", true);
  set_camera_errors_and_mask(*model);
  return model;
}

}  // namespace

void register_camera(ModelRegistry& registry) {
  registry.add_sensor({"camera",
                       "a camera seeing the points of a target (a chessboard, a circle grid or "
                       "given points), fixed and seeing a target on the end effector or carried "
                       "and seeing a fixed one: pinhole with Brown-Conrady distortion, two "
                       "readings u, v per point in px",
                       read_camera, write_camera});
  registry.add_preset(
      {"ur5-urdf-camera",
       "the ur5-urdf arm (0.25 rad per joint around home) with a 6 x 8 "
       "chessboard on a bracket at its flange seen by a fixed 1280 x 1024 camera "
       "800 mm away (eye-to-hand); free: the camera's intrinsics and distortion but "
       "k3, both mounts and the arm's parameters the views determine",
       make_ur5_urdf_camera});
  registry.add_preset({"cube-hexapod-camera",
                       "the paper's cube hexapod (cube-hexapod's free set) seen by a 1280 x "
                       "1024 camera 800 mm above a 6 x 8 chessboard on its platform "
                       "(eye-to-hand); free: the camera's intrinsics and distortion but k3 and "
                       "both mounts",
                       make_cube_hexapod_camera});
  registry.add_preset({"flange-pose-camera",
                       "a robot known by its reported flange poses (flange-pose) carrying a 10 x "
                       "10 circle grid seen by a fixed 640 x 480 camera 700 mm away "
                       "(eye-to-hand, a hand-eye data set's cell); free: the camera's "
                       "intrinsics and distortion but k3 and both mounts",
                       make_flange_pose_camera});
  registry.add_preset({"ur5-urdf-eye-in-hand",
                       "the ur5-urdf arm (0.25 rad per joint around home) carrying a 1280 x "
                       "1024 camera that sees a 6 x 8 chessboard on the table 400 mm away "
                       "(eye-in-hand); "
                       "free: the camera's intrinsics and distortion but k3, both mounts and "
                       "the arm's parameters the views determine",
                       make_ur5_urdf_eye_in_hand});
}

}  // namespace kincal
