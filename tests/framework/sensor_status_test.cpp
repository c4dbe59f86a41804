// A sensor that can say "no reading" (Sensor::can_miss / reads_at): a laser distance sensor
// on the platform whose beam must hit a plane of the base, written once as a function
// template (framework/kinematics/autodiff.hpp) with its beam and plane directions as azimuth and
// elevation. Its reading is dropped where the beam grazes the plane or the plane is out of
// range, without dropping the configuration's other readings; a measured reading that it
// cannot take at the parameters being evaluated fails the evaluation, as forward kinematics
// does.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "jacobian_check.hpp"
#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/kinematics/autodiff.hpp"
#include "kincal/models/hexapod.hpp"
#include "kincal/models/length_gauge.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

// Distance along a beam from a platform point, direction (azimuth, elevation) in the platform
// frame, to the base plane n . x = c, n at (azimuth, elevation) in the base frame:
//   reading = (c - n . o) / (n . u),  o = R o_p + t,  u = R u_p.
class LaserDistance final : public AutoDiffSensor<LaserDistance, 8, 1> {
 public:
  enum { kOrigin = 0, kBeam = 3, kNormal = 5, kOffset = 7 };
  /// The beam misses beyond this angle from the plane's normal or this range.
  static constexpr double kMaxIncidence = 80 * M_PI / 180, kMaxRange = 415;

  explicit LaserDistance(const VectorXd& nominal) {
    const char* names[8] = {"origin.x",       "origin.y",      "origin.z",        "beam.azimuth",
                            "beam.elevation", "plane.azimuth", "plane.elevation", "plane.offset"};
    const char* units[8] = {"mm", "mm", "mm", "rad", "rad", "rad", "rad", "mm"};
    for (int i = 0; i < 8; ++i)
      parameters_.push_back({name_ + "." + names[i], nominal[i], units[i], false});
  }
  std::string type() const override { return "laser-distance"; }
  const std::string& name() const override { return name_; }
  std::vector<std::string> reading_units() const override { return {"mm"}; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }

  template <class T>
  static Eigen::Matrix<T, 3, 1> direction(const T& azimuth, const T& elevation) {
    using std::cos;
    using std::sin;
    return {cos(elevation) * cos(azimuth), cos(elevation) * sin(azimuth), sin(elevation)};
  }
  // n . u and the distance along the beam.
  template <class T>
  static void beam(const T* p, const PoseT<T>& pose, T& cosine, T& distance) {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> origin(p + kOrigin);
    const Eigen::Matrix<T, 3, 1> o = pose.transform_point(origin);
    const Eigen::Matrix<T, 3, 1> u = pose.rotation * direction(p[kBeam], p[kBeam + 1]);
    const Eigen::Matrix<T, 3, 1> n = direction(p[kNormal], p[kNormal + 1]);
    cosine = n.dot(u);
    distance = (p[kOffset] - n.dot(o)) / cosine;
  }
  template <class T>
  void autodiff_readings(const T* params, const PoseT<T>& pose, T* readings) const {
    T cosine;
    beam(params, pose, cosine, readings[0]);
  }

  bool can_miss() const override { return true; }
  bool reads_at(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
                std::string* reason) const override {
    double cosine, distance;
    beam(params.data(), ad::to_pose_t(pose), cosine, distance);
    std::string why;
    if (!(std::abs(cosine) > std::cos(kMaxIncidence)))
      why = "beam grazes the plane";
    else if (!(distance > 0))
      why = "plane behind the beam";
    else if (!(distance <= kMaxRange))
      why = "plane out of range";
    if (why.empty()) return true;
    if (reason) *reason = why;
    return false;
  }

 private:
  std::string name_ = "laser";
  std::vector<Parameter> parameters_;
};

// The laser points down (elevation -90 degrees) from the platform's centre at the floor
// z = 0: 410 mm away at home, out of range (415 mm) when the platform rises 5 mm more.
VectorXd laser_nominal() {
  return (VectorXd(8) << 0, 0, 0, 0, -M_PI / 2 + 0.05, 0, M_PI / 2, 0).finished();
}

std::shared_ptr<MeasurementModel> model_with_laser() {
  HexapodGeometry g;
  g.base_joints = {Vector3d(-140, -140, 28), Vector3d(-140, 140, 28), Vector3d(140, 0, 28),
                   Vector3d(177, 70, 130),   Vector3d(177, -70, 130), Vector3d(0, -205, 280)};
  g.platform_joints = {Vector3d(-140, -140, -28), Vector3d(-140, 140, -28),
                       Vector3d(140, 0, -28),     Vector3d(-177, 70, -280),
                       Vector3d(-177, -70, -280), Vector3d(0, 177, -140)};
  g.home.translation = Vector3d(0, 0, 410);
  auto gauge =
      std::make_shared<LengthGauge>("gauge", Vector3d(-200, 500, 500), Vector3d(-200, 205, -5));
  auto laser = std::make_shared<LaserDistance>(laser_nominal());
  return std::make_shared<MeasurementModel>(
      std::make_shared<Hexapod>(g), std::vector<std::shared_ptr<const Sensor>>{gauge, laser});
}

// Actuator values that put the platform at height z (home otherwise).
VectorXd actuators_at_height(const MeasurementModel& model, double z) {
  Pose pose = model.mechanism().home_pose();
  pose.translation.z() = z;
  VectorXd q(6);
  const auto ik = model.mechanism().inverse_kinematics(
      model.parameters().nominal_values().head(model.mechanism().num_parameters()), pose, q);
  EXPECT_TRUE(ik.ok()) << ik.describe();
  return q;
}

TEST(SensorStatus, AutomaticDerivativesOfTheLaserMatchFiniteDifferences) {
  const LaserDistance laser(laser_nominal());
  const VectorXd params = laser_nominal() + VectorXd::LinSpaced(8, 0.01, 0.08);
  Pose pose;
  pose.translation = Vector3d(3, -4, 400);
  pose.rotation = exp_so3(Vector3d(0.05, -0.03, 0.2));
  VectorXd r(1);
  MatrixXd J_pose(1, 6), J_params(1, 8);
  laser.predict(params, pose, r, &J_pose, &J_params);
  auto at_params = [&](const VectorXd& p) {
    VectorXd out(1);
    laser.predict(p, pose, out, nullptr, nullptr);
    return out;
  };
  auto at_pose = [&](const VectorXd& delta) {
    VectorXd out(1);
    laser.predict(params, perturb(pose, delta), out, nullptr, nullptr);
    return out;
  };
  EXPECT_GT(r[0], 390);
  EXPECT_TRUE(jacobians_match(J_params, numerical_jacobian(at_params, params, 1e-6), 1e-6));
  EXPECT_TRUE(jacobians_match(J_pose, numerical_jacobian(at_pose, VectorXd::Zero(6), 1e-6), 1e-6));
}

TEST(SensorStatus, TheLaserSaysWhyItGivesNoReading) {
  const LaserDistance laser(laser_nominal());
  Pose pose;
  pose.translation.z() = 410;
  std::string reason;
  EXPECT_TRUE(laser.reads_at(laser_nominal(), pose, &reason));
  pose.translation.z() = 420;
  EXPECT_FALSE(laser.reads_at(laser_nominal(), pose, &reason));
  EXPECT_EQ(reason, "plane out of range");
  pose.translation.z() = -10;
  EXPECT_FALSE(laser.reads_at(laser_nominal(), pose, &reason));
  EXPECT_EQ(reason, "plane behind the beam");
  pose.translation.z() = 410;
  pose.rotation = exp_so3(Vector3d(M_PI / 2, 0, 0));
  EXPECT_FALSE(laser.reads_at(laser_nominal(), pose, &reason));
  EXPECT_EQ(reason, "beam grazes the plane");
}

TEST(SensorStatus, PredictDropsOnlyTheMissedReading) {
  const auto model = model_with_laser();
  EXPECT_TRUE(model->sensors_can_miss());
  const VectorXd params = model->parameters().nominal_values();
  auto ws = model->make_workspace();
  VectorXd readings(2);
  MatrixXd J = MatrixXd::Constant(2, model->num_parameters(), 7.0);
  Eigen::Ref<MatrixXd> J_ref(J);
  ASSERT_TRUE(model->predict(params, actuators_at_height(*model, 405), readings, &J_ref, ws).ok());
  EXPECT_TRUE(std::isfinite(readings[1]));
  EXPECT_NE(J.row(1).norm(), 0.0);

  ASSERT_TRUE(model->predict(params, actuators_at_height(*model, 420), readings, &J_ref, ws).ok());
  EXPECT_TRUE(std::isfinite(readings[0])) << "the gauge still reads";
  EXPECT_NE(J.row(0).norm(), 0.0);
  EXPECT_TRUE(std::isnan(readings[1])) << "the laser is out of range";
  EXPECT_EQ(J.row(1).norm(), 0.0);

  VectorXd at_pose(2);
  Pose high = model->mechanism().home_pose();
  high.translation.z() = 420;
  model->predict_at_pose(params, high, at_pose);
  EXPECT_TRUE(std::isfinite(at_pose[0]));
  EXPECT_TRUE(std::isnan(at_pose[1]));
}

TEST(SensorStatus, SimulationLeavesMissedReadingsUnmeasured) {
  ScenarioOptions options;
  options.num_configurations = 40;
  options.num_validation = 0;
  options.seed = 7;
  const Scenario s = make_scenario(model_with_laser(), options);
  const auto present = s.calibration.present_per_column();
  EXPECT_EQ(present[0], 40) << "the gauge reads everywhere";
  EXPECT_GT(present[1], 0);
  EXPECT_LT(present[1], 40) << "the laser must miss somewhere for this test to mean anything";
  // The missed readings do not stop a calibration from evaluating.
  std::string why;
  VectorXd r;
  MatrixXd J;
  const auto problem = s.make_problem();
  EXPECT_TRUE(problem->evaluate(problem->initial_free_parameters(), &r, &J, &why)) << why;
}

Measurements three_rows(const MeasurementModel& model) {
  Measurements data;
  data.actuators.resize(3, 6);
  data.actuators.row(0) = actuators_at_height(model, 405).transpose();
  data.actuators.row(1) = actuators_at_height(model, 420).transpose();
  data.actuators.row(2) = actuators_at_height(model, 420).transpose();
  data.readings.resize(3, 2);
  data.readings << 400, 405, 401, 420, std::numeric_limits<double>::quiet_NaN(), 420;
  return data;
}

TEST(SensorStatus, ReadingTheDataDropsMissedReadingsAndRowsWithoutAny) {
  const auto model = model_with_laser();
  const VectorXd params = model->parameters().nominal_values();
  Measurements data = three_rows(*model);
  // Row 3 measured only the laser, which cannot read there: the row is unusable.
  const auto bad = find_unreachable_rows(*model, params, data);
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_EQ(bad[0].row, 2);
  EXPECT_EQ(bad[0].reason, "gives no reading (laser: plane out of range)");
  // Row 2 keeps its gauge reading; its laser reading goes.
  const auto missed = find_missed_readings(*model, params, data);
  ASSERT_EQ(missed.size(), 1u);
  EXPECT_EQ(missed[0].row, 1);
  EXPECT_EQ(missed[0].sensor, 1);
  EXPECT_EQ(missed[0].reason, "plane out of range");
  drop_readings(*model, missed, data);
  EXPECT_EQ(data.readings(1, 0), 401);
  EXPECT_TRUE(std::isnan(data.readings(1, 1)));
  EXPECT_EQ(data.readings(0, 1), 405);
}

TEST(SensorStatus, AMeasuredReadingTheSensorCannotTakeFailsTheEvaluation) {
  const auto model = model_with_laser();
  model->parameters().set_free("laser.plane.offset", true);
  Measurements data = three_rows(*model);
  data.readings(1, 1) = std::numeric_limits<double>::quiet_NaN();  // as dropped when read
  data.readings(2, 0) = 402;
  data.readings(2, 1) = std::numeric_limits<double>::quiet_NaN();
  CalibrationProblem problem(model, data, model->parameters().nominal_values(),
                             {model->num_parameters() - 1});
  VectorXd x(1), r;
  MatrixXd J;
  std::string why;
  x[0] = 0;
  EXPECT_TRUE(problem.evaluate(x, &r, &J, &why)) << why;
  x[0] = -20;  // the floor 20 mm lower: row 1's laser (405 mm) now out of range
  EXPECT_FALSE(problem.evaluate(x, &r, &J, &why));
  EXPECT_EQ(why, "configuration 1: sensor laser: no reading: plane out of range");
}

TEST(SensorStatus, TheReportCountsDroppedReadings) {
  CalibrationReport report;
  report.dropped_readings = {"line 3: laser: plane out of range"};
  const auto json = to_json(report);
  ASSERT_TRUE(json.contains("dropped_readings"));
  EXPECT_EQ(json["dropped_readings"][0], "line 3: laser: plane out of range");
  EXPECT_NE(to_text(report).find("(1 readings dropped: no reading)"), std::string::npos);
}

}  // namespace
}  // namespace kincal
