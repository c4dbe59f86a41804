// Starting values for a camera without guesses (models/camera_start.hpp): a view's target pose
// from its pixels alone, both mounts from the closed-form hand-eye solution, and the per-view
// cross-check; and what a measurement file may hold for a camera (points missing one by one,
// never half a point, never a pixel outside the image).

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/camera_start.hpp"

namespace kincal {
namespace {

// Views of `model` at its nominal values: configurations drawn within the actuators' default
// ranges around home, the readings a camera would take (points out of view missing), rows
// with fewer than 6 points left out.
Measurements views(const MeasurementModel& model, int count, unsigned seed) {
  const Mechanism& mechanism = model.mechanism();
  const VectorXd params = model.parameters().nominal_values();
  const auto mech_params = params.head(mechanism.num_parameters());
  VectorXd home(mechanism.num_actuators());
  EXPECT_TRUE(mechanism.home_actuators(mech_params, home).ok());
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<VectorXd> qs, readings;
  for (int attempt = 0; attempt < 50 * count && static_cast<int>(qs.size()) < count; ++attempt) {
    VectorXd q = home;
    for (int i = 0; i < q.size(); ++i)
      q[i] += uniform(random) * mechanism.actuators()[static_cast<std::size_t>(i)].default_range;
    const auto fk = mechanism.forward_kinematics(mech_params, q, mechanism.home_pose());
    if (!fk.ok()) continue;
    VectorXd r(model.num_readings());
    model.simulate_at_pose(params, fk.pose, r);
    if ((r.array() == r.array()).count() < 12) continue;
    qs.push_back(q);
    readings.push_back(r);
  }
  Measurements data;
  data.actuators.resize(static_cast<Eigen::Index>(qs.size()), mechanism.num_actuators());
  data.readings.resize(static_cast<Eigen::Index>(qs.size()), model.num_readings());
  for (std::size_t k = 0; k < qs.size(); ++k) {
    data.actuators.row(static_cast<Eigen::Index>(k)) = qs[k].transpose();
    data.readings.row(static_cast<Eigen::Index>(k)) = readings[k].transpose();
  }
  return data;
}

double frame_distance(const Vector6d& a, const Vector6d& b) {
  const Pose pa = frame_from_parameters(a), pb = frame_from_parameters(b);
  return (pa.translation - pb.translation).norm() +
         1000 * log_so3(pa.rotation.transpose() * pb.rotation).norm();
}

class CameraStart : public ::testing::TestWithParam<const char*> {};

TEST_P(CameraStart, RecoversBothMountsFromExactViews) {
  const auto model = ModelRegistry::global().make_preset(GetParam());
  const Measurements data = views(*model, 15, 5);
  ASSERT_GE(data.size(), 10);
  const VectorXd truth = model->parameters().nominal_values();
  // The mounts' values are not used: zero them to be sure.
  VectorXd params = truth;
  const int offset = model->sensor_parameter_offset(0);
  params.segment(offset + Camera::kFrameIndex, 12).setZero();
  const CameraMountStart start = estimate_camera_mounts(*model, 0, params, data);
  ASSERT_TRUE(start.ok) << start.reason;
  EXPECT_EQ(start.views_used, data.size());
  for (const ViewPose& view : start.views) {
    EXPECT_TRUE(view.ok) << view.reason;
    EXPECT_LT(view.rms_px, 1e-6);
  }
  EXPECT_LT(frame_distance(start.frame, truth.segment<6>(offset + Camera::kFrameIndex)), 1e-5);
  EXPECT_LT(frame_distance(start.target, truth.segment<6>(offset + Camera::kTargetIndex)), 1e-5);

  // The cross-check at the truth: every view agrees with the model.
  for (const ViewCheck& check : check_views(*model, 0, truth, data)) {
    ASSERT_TRUE(check.ok) << check.reason;
    EXPECT_LT(check.position, 1e-5);
    EXPECT_LT(check.angle, 1e-8);
  }
}

INSTANTIATE_TEST_SUITE_P(Mountings, CameraStart,
                         ::testing::Values("flange-pose-camera", "ur5-urdf-eye-in-hand",
                                           "ur5-urdf-camera"));

TEST(CameraStart, AViewWhosePoseRowBelongsToAnotherImageIsNamed) {
  const auto model = ModelRegistry::global().make_preset("flange-pose-camera");
  Measurements data = views(*model, 12, 13);
  ASSERT_GE(data.size(), 10);
  std::mt19937 random(4);
  std::normal_distribution<double> noise(0, 0.2);  // px
  for (Eigen::Index i = 0; i < data.readings.size(); ++i)
    if (!std::isnan(data.readings.data()[i])) data.readings.data()[i] += noise(random);
  data.actuators.row(3).swap(data.actuators.row(7));  // two pose rows exchanged
  const VectorXd truth = model->parameters().nominal_values();
  const auto checks = check_views(*model, 0, truth, data);
  EXPECT_EQ(disagreeing_views(checks), (std::vector<int>{3, 7}));
  std::vector<std::string> labels;
  for (int k = 0; k < data.size(); ++k) labels.push_back("V.csv:" + std::to_string(k + 2));
  const std::string text = view_checks_text("camera", checks, labels);
  EXPECT_NE(text.find("V.csv:5 disagrees"), std::string::npos) << text;
  EXPECT_NE(text.find("V.csv:9 disagrees"), std::string::npos) << text;
  EXPECT_EQ(view_checks_json("camera", checks, labels)["disagreeing"].size(), 2u);
}

TEST(CameraStart, NoisyPixelsGiveMountsNearTheTruth) {
  const auto model = ModelRegistry::global().make_preset("flange-pose-camera");
  Measurements data = views(*model, 20, 9);
  std::mt19937 random(2);
  std::normal_distribution<double> noise(0, 0.3);  // px
  for (Eigen::Index i = 0; i < data.readings.size(); ++i)
    if (!std::isnan(data.readings.data()[i])) data.readings.data()[i] += noise(random);
  const VectorXd truth = model->parameters().nominal_values();
  const CameraMountStart start = estimate_camera_mounts(*model, 0, truth, data);
  ASSERT_TRUE(start.ok) << start.reason;
  const int offset = model->sensor_parameter_offset(0);
  // A start, not an estimate: within a few mm (and mrad, weighted as mm) of the truth.
  EXPECT_LT(frame_distance(start.frame, truth.segment<6>(offset + Camera::kFrameIndex)), 20);
  EXPECT_LT(frame_distance(start.target, truth.segment<6>(offset + Camera::kTargetIndex)), 20);
  for (const ViewPose& view : start.views) EXPECT_LT(view.rms_px, 1.0);
}

TEST(CameraStart, AViewWithTooFewPointsHasNoPoseAndSaysWhy) {
  const auto model = ModelRegistry::global().make_preset("flange-pose-camera");
  const auto& camera = dynamic_cast<const Camera&>(*model->sensors()[0]);
  const VectorXd params = model->parameters().nominal_values().segment(
      model->sensor_parameter_offset(0), camera.num_parameters());
  VectorXd reading = VectorXd::Constant(camera.num_readings(), std::nan(""));
  reading.head<6>() << 100, 100, 120, 100, 140, 100;  // three points
  const ViewPose view = solve_view_pose(camera, params, reading);
  EXPECT_FALSE(view.ok);
  EXPECT_NE(view.reason.find("3 points"), std::string::npos) << view.reason;
}

// A measurement file for the flange-pose camera with the given readings of points p0, p1 (the
// rest empty).
std::string camera_file(const MeasurementModel& model, const std::string& p0,
                        const std::string& p1) {
  std::ostringstream csv;
  for (const auto& name : model.mechanism().actuator_names()) csv << name << ',';
  const auto names = model.reading_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    csv << names[i] << (i + 1 < names.size() ? "," : "\n");
  csv << "0,0,0,0,0,0," << p0 << ',' << p1;
  for (std::size_t i = 4; i < names.size(); ++i) csv << ',';
  csv << '\n';
  return csv.str();
}

MeasurementTable read_camera_file(const MeasurementModel& model, const std::string& text) {
  std::istringstream in(text);
  MeasurementTable table =
      parse_measurements(in, "D.csv", model.mechanism().actuator_names(), model.reading_names());
  check_sensor_readings(model, table, "D.csv");
  return table;
}

TEST(CameraReadings, PointsAreMissingOneByOneNeverHalfAPoint) {
  const auto model = ModelRegistry::global().make_preset("flange-pose-camera");
  const MeasurementTable table = read_camera_file(*model, camera_file(*model, "100,200", ","));
  EXPECT_EQ(table.data.num_present(), 2);
  try {
    read_camera_file(*model, camera_file(*model, "100,200", "300,"));
    FAIL() << "half a point was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("D.csv:2: sensor 'camera' has camera.p1.u but not "
                                         "camera.p1.v"),
              std::string::npos)
        << e.what();
  }
}

TEST(CameraReadings, APixelOutsideTheImageIsRefusedWithItsLine) {
  const auto model = ModelRegistry::global().make_preset("flange-pose-camera");
  try {
    read_camera_file(*model, camera_file(*model, "100,200", "700,100"));
    FAIL() << "a pixel outside the 640 px image was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("D.csv:2: camera.p1.u: u = 700 px is outside the image"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace kincal
