// The serial arm: known forward kinematics of the presets, Jacobians of arms the presets do
// not cover (prismatic joints, base and tool frames), Hayati against DH, inverse kinematics'
// failure statuses, model-file errors, and the presets' identifiability.

#include "kincal/models/serial_arm.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "jacobian_check.hpp"
#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/least_squares/uncertainty.hpp"
#include "kincal/models/serial_arm_presets.hpp"

namespace kincal {
namespace {

using kincal::testing::jacobians_match;
using kincal::testing::numerical_jacobian;

Vector6d pose_difference(const Pose& from, const Pose& to) {
  Vector6d d;
  d << to.translation - from.translation, log_so3(to.rotation * from.rotation.transpose());
  return d;
}

const SerialArm& arm_of(const MeasurementModel& model) {
  return dynamic_cast<const SerialArm&>(model.mechanism());
}

SerialJoint joint(const std::string& name, JointType type, LinkConvention convention, double a,
                  double alpha, double d_or_beta, double theta) {
  SerialJoint j;
  j.name = name;
  j.type = type;
  j.convention = convention;
  j.a = a;
  j.alpha = alpha;
  (convention == LinkConvention::kDh ? j.d : j.beta) = d_or_beta;
  j.theta = theta;
  return j;
}

// Five joints of every kind, between a base and a tool that are not the identity.
SerialArmGeometry mixed_arm() {
  SerialArmGeometry g;
  g.base << 100, -50, 300, 0.1, -0.2, 0.3;
  g.joints = {joint("j1", JointType::kRevolute, LinkConvention::kDh, 20, kPi / 2, 350, 0.1),
              joint("j2", JointType::kRevolute, LinkConvention::kHayati, 400, 0.01, 0.02, -0.2),
              joint("slide", JointType::kPrismatic, LinkConvention::kDh, 15, -kPi / 2, 100, 0.3),
              joint("j4", JointType::kRevolute, LinkConvention::kDh, 5, kPi / 2, 250, 0.05),
              joint("j5", JointType::kRevolute, LinkConvention::kHayati, 80, -0.03, 0.01, 0.4)};
  g.tool << 10, 20, 150, 0.6, 0.25, -0.4;
  return g;
}

std::vector<std::string> names_of(const Mechanism& m) {
  std::vector<std::string> names;
  for (const auto& p : m.parameters()) names.push_back(p.name);
  return names;
}

VectorXd random_joints(Random& rng, int n, double half_width) {
  VectorXd q(n);
  for (int i = 0; i < n; ++i) q[i] = rng.symmetric(half_width);
  return q;
}

TEST(SerialArm, Puma560AtZeroIsTheLShapeOfTheToolbox) {
  // Hand-computed from the DH table (and what the Robotics Toolbox's fkine(qz) prints): the
  // upper arm along x (431.8), the forearm up (d4 = 431.8), the shoulder offset d3 = 150.05
  // along -y and a3 = 20.3 along x, the wrist frame parallel to the base.
  const auto model = make_puma560();
  const SerialArm& arm = arm_of(*model);
  const auto fk =
      arm.forward_kinematics(model->parameters().nominal_values().head(arm.num_parameters()),
                             VectorXd::Zero(6), arm.home_pose());
  ASSERT_TRUE(fk.ok());
  EXPECT_LT((fk.pose.translation - Vector3d(452.1, -150.05, 431.8)).norm(), 1e-12);
  EXPECT_LT((fk.pose.rotation - Matrix3d::Identity()).norm(), 1e-15);
}

TEST(SerialArm, Ur5AtZeroIsStretchedAlongMinusX) {
  // Hand-computed from Universal Robots' table: x = a2 + a3, y = -(d4 + d6), z = d1 - d5,
  // and the flange's z axis along -y (R = Rx(90 degrees)).
  const auto model = make_ur5();
  const SerialArm& arm = arm_of(*model);
  const auto fk =
      arm.forward_kinematics(model->parameters().nominal_values().head(arm.num_parameters()),
                             VectorXd::Zero(6), arm.home_pose());
  ASSERT_TRUE(fk.ok());
  EXPECT_LT((fk.pose.translation - Vector3d(-817.25, -191.45, -5.491)).norm(), 1e-12);
  Matrix3d expected;
  expected << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  EXPECT_LT((fk.pose.rotation - expected).norm(), 1e-15);
}

TEST(SerialArm, HomeIsTheModelsHomeJointsAndItsForwardKinematics) {
  const auto model = make_puma560();
  const SerialArm& arm = arm_of(*model);
  VectorXd q(6);
  const VectorXd params = model->parameters().nominal_values().head(arm.num_parameters());
  ASSERT_TRUE(arm.home_actuators(params, q).ok());
  VectorXd expected(6);
  expected << 0, kPi / 4, kPi, 0, kPi / 4, 0;
  EXPECT_LT((q - expected).norm(), 1e-15);
  const auto fk = arm.forward_kinematics(params, q, Pose{});
  EXPECT_LT(pose_difference(fk.pose, arm.home_pose()).norm(), 1e-15);
  for (const auto& a : arm.actuators()) {
    EXPECT_EQ(a.unit, "rad");
    EXPECT_EQ(a.default_range, SerialArm::kDefaultRevoluteRange);
  }
}

TEST(SerialArm, PrismaticJointSlidesAlongItsAxisByItsValue) {
  SerialArmGeometry g;
  g.joints = {joint("lift", JointType::kPrismatic, LinkConvention::kDh, 0, 0, 100, 0),
              joint("turn", JointType::kRevolute, LinkConvention::kDh, 200, 0, 0, 0)};
  const SerialArm arm(g);
  EXPECT_EQ(arm.actuators()[0].unit, "mm");
  EXPECT_EQ(arm.actuators()[0].default_range, SerialArm::kDefaultPrismaticRange);
  EXPECT_EQ(arm.parameters()[SerialArm::joint_index(0) + SerialArm::kDOrBeta].name, "lift.d");
  const VectorXd params = serial_arm_parameters(g);
  const auto at = [&](double lift, double turn) {
    return arm.forward_kinematics(params, Eigen::Vector2d(lift, turn), Pose{}).pose.translation;
  };
  EXPECT_LT((at(0, 0) - Vector3d(200, 0, 100)).norm(), 1e-12);
  EXPECT_LT((at(25, 0) - Vector3d(200, 0, 125)).norm(), 1e-12);
  EXPECT_LT((at(25, kPi / 2) - Vector3d(0, 200, 125)).norm(), 1e-12);
}

TEST(SerialArm, PoseJacobiansMatchFiniteDifferences) {
  const SerialArm arm(mixed_arm());
  const VectorXd params = serial_arm_parameters(mixed_arm());
  Random rng(31);
  for (int trial = 0; trial < 5; ++trial) {
    const VectorXd q = random_joints(rng, arm.num_joints(), 1.0);
    const auto fk = arm.forward_kinematics(params, q, Pose{});
    ASSERT_TRUE(fk.ok());
    Matrix6Xd J_params(6, arm.num_parameters()), J_q(6, arm.num_joints());
    arm.pose_jacobian_params(params, q, fk.pose, J_params);
    const Pose at_q = arm.joint_jacobian(params, q, J_q);
    EXPECT_LT(pose_difference(fk.pose, at_q).norm(), 1e-15);
    auto by_params = [&](const VectorXd& p) -> VectorXd {
      return pose_difference(fk.pose, arm.forward_kinematics(p, q, Pose{}).pose);
    };
    auto by_joints = [&](const VectorXd& x) -> VectorXd {
      return pose_difference(fk.pose, arm.forward_kinematics(params, x, Pose{}).pose);
    };
    EXPECT_TRUE(
        jacobians_match(J_params, numerical_jacobian(by_params, params, 1e-5), 1e-7, names_of(arm)))
        << "trial " << trial;
    EXPECT_TRUE(jacobians_match(J_q, numerical_jacobian(by_joints, q, 1e-5), 1e-7))
        << "trial " << trial;
  }
}

TEST(SerialArm, HayatiLinkWithoutTiltIsTheDhLinkWithoutOffset) {
  // With beta = 0 and d = 0 the two conventions describe the same link.
  SerialArmGeometry dh = mixed_arm(), hayati = mixed_arm();
  dh.joints[1].convention = LinkConvention::kDh;
  dh.joints[1].d = 0;
  hayati.joints[1].beta = 0;
  const SerialArm dh_arm(dh), hayati_arm(hayati);
  Random rng(32);
  for (int trial = 0; trial < 10; ++trial) {
    const VectorXd q = random_joints(rng, 5, 2.0);
    const auto a = dh_arm.forward_kinematics(serial_arm_parameters(dh), q, Pose{});
    const auto b = hayati_arm.forward_kinematics(serial_arm_parameters(hayati), q, Pose{});
    EXPECT_LT(pose_difference(a.pose, b.pose).norm(), 1e-12);
  }
}

TEST(SerialArm, HayatiTiltIsARotationAboutTheNewYAxis) {
  // A Hayati link with beta is the beta = 0 link followed by Ry(beta) at the new origin.
  SerialArmGeometry g;
  g.joints = {joint("j1", JointType::kRevolute, LinkConvention::kHayati, 300, 0.2, 0.05, 0.1)};
  const SerialArm arm(g);
  const double q = 0.7;
  const Pose end =
      arm.forward_kinematics(serial_arm_parameters(g), VectorXd::Constant(1, q), Pose{}).pose;
  const double theta = 0.1 + q;
  const Matrix3d expected = Eigen::AngleAxisd(theta, Vector3d::UnitZ()).toRotationMatrix() *
                            Eigen::AngleAxisd(0.2, Vector3d::UnitX()).toRotationMatrix() *
                            Eigen::AngleAxisd(0.05, Vector3d::UnitY()).toRotationMatrix();
  EXPECT_LT((end.rotation - expected).norm(), 1e-15);
  EXPECT_LT((end.translation - Vector3d(300 * std::cos(theta), 300 * std::sin(theta), 0)).norm(),
            1e-12);
}

// The identification Jacobian of a preset's default scenario with `edit` applied to its
// free mask, at the nominal parameters (where a calibration starts, and what
// `kincal observability` analyses).
Identifiability identifiability_of(std::shared_ptr<MeasurementModel> model,
                                   const std::function<void(ParameterSet&)>& edit = {},
                                   std::uint64_t seed = 1) {
  if (edit) edit(model->parameters());
  ScenarioOptions options;
  options.num_validation = 0;
  options.seed = seed;
  const Scenario s = make_scenario(model, options);
  CalibrationProblem problem(model, s.calibration, s.nominal, s.free_indices);
  VectorXd r;
  MatrixXd J;
  std::string why;
  EXPECT_TRUE(problem.evaluate(problem.initial_free_parameters(), &r, &J, &why)) << why;
  return analyze_identifiability(J, problem.parameter_names());
}

TEST(SerialArm, DhIsRankDeficientAcrossParallelAxesAndHayatiIsNot) {
  // With DH on the PUMA's parallel joints 2-3, joint2.d and joint3.d both slide along the
  // same direction: the data cannot tell them apart. Hayati's beta in place of joint2.d is
  // determined.
  const auto hayati = make_puma560();
  const SerialArm& arm = arm_of(*hayati);
  SerialArmGeometry g = arm.nominal_geometry();
  g.joints[1].convention = LinkConvention::kDh;
  g.joints[1].d = 0;
  auto dh = std::make_shared<MeasurementModel>(std::make_shared<SerialArm>(g), hayati->sensors());
  for (int i : hayati->parameters().free_indices())
    dh->parameters().set_free(hayati->parameters()[i].name == "joint2.beta"
                                  ? std::string("joint2.d")
                                  : hayati->parameters()[i].name,
                              true);
  const Identifiability with_dh = identifiability_of(dh);
  ASSERT_EQ(with_dh.num_parameters, 27);
  EXPECT_EQ(with_dh.numerical_rank, 26);
  ASSERT_FALSE(with_dh.combinations.empty());
  const std::string weakest = with_dh.combinations.front().describe();
  EXPECT_NE(weakest.find("joint2.d"), std::string::npos) << weakest;
  EXPECT_NE(weakest.find("joint3.d"), std::string::npos) << weakest;
  EXPECT_FALSE(identifiability_of(make_puma560()).rank_deficient());
}

TEST(SerialArm, PresetMasksAreFullRankWithAMargin) {
  // The known counts of independent parameters of a 6R arm: 4 per revolute joint + 6 with
  // full pose measurement (30), 3 fewer with position only (27). Both masks are full rank on
  // default simulations, far from the rank threshold (a condition number of 1e6): measured
  // 372-507 (puma560) and 381-535 (ur5) over these seeds, printed here and quoted in
  // docs/theory.md.
  const std::vector<std::pair<std::string, int>> presets = {{"puma560", 27}, {"ur5", 30}};
  for (const auto& [name, count] : presets) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const Identifiability id =
          identifiability_of(ModelRegistry::global().make_preset(name), {}, seed);
      EXPECT_EQ(id.num_parameters, count) << name;
      EXPECT_EQ(id.numerical_rank, count) << name << " seed " << seed;
      EXPECT_LT(id.condition_number, 1e4) << name << " seed " << seed;
      std::printf("%s seed %d: %d free, rank %d, condition number %.4g\n", name.c_str(),
                  static_cast<int>(seed), id.num_parameters, id.numerical_rank,
                  id.condition_number);
    }
  }
}

TEST(SerialArm, EveryParameterTheMasksFixIsRedundantOrUnseen) {
  // Freeing any one fixed parameter of a preset makes the Jacobian rank deficient: the mask
  // is maximal, not merely sufficient.
  for (const auto& make : {make_puma560, make_ur5}) {
    const auto model = make();
    for (int i = 0; i < model->num_parameters(); ++i) {
      if (model->parameters()[i].free) continue;
      const std::string name = model->parameters()[i].name;
      const Identifiability id =
          identifiability_of(make(), [&](ParameterSet& p) { p.set_free(name, true); });
      EXPECT_TRUE(id.rank_deficient()) << name << ": condition " << id.condition_number;
    }
  }
}

TEST(SerialArm, InverseKinematicsSolvesPosesInTheWorkspace) {
  // A 5-joint arm reaches the poses of its own forward kinematics, and so does a redundant
  // 7-joint one (damping keeps its 7 x 7 normal equations solvable), from home.
  SerialArmGeometry seven = mixed_arm();
  seven.joints.push_back(joint("j6", JointType::kRevolute, LinkConvention::kDh, 30, -1.2, 60, 0));
  seven.joints.push_back(joint("j7", JointType::kRevolute, LinkConvention::kDh, 0, 0.8, 90, 0));
  for (const SerialArmGeometry& g : {mixed_arm(), seven}) {
    const SerialArm arm(g);
    const VectorXd params = serial_arm_parameters(g);
    Random rng(33);
    for (int trial = 0; trial < 5; ++trial) {
      const VectorXd target_q = random_joints(rng, arm.num_joints(), 0.5);
      const Pose target = arm.forward_kinematics(params, target_q, Pose{}).pose;
      VectorXd q(arm.num_joints());
      const auto ik = arm.inverse_kinematics(params, target, q);
      ASSERT_TRUE(ik.ok()) << arm.num_joints() << " joints: " << ik.describe();
      EXPECT_LT(pose_difference(target, arm.forward_kinematics(params, q, Pose{}).pose).norm(),
                1e-9);
    }
  }
}

TEST(SerialArm, InverseKinematicsReportsUnreachableAndNotConverged) {
  // Fewer than six joints: a pose off the arm's 5-dimensional set is unreachable.
  const SerialArm arm(mixed_arm());
  const VectorXd params = serial_arm_parameters(mixed_arm());
  Pose target = arm.home_pose();
  target.rotation = exp_so3(Vector3d(0.3, 0.0, 0.0)) * target.rotation;
  VectorXd q(5);
  const auto unreachable = arm.inverse_kinematics(params, target, q);
  EXPECT_EQ(unreachable.status, InverseKinematicsStatus::kUnreachable) << unreachable.describe();
  EXPECT_GT(unreachable.residual_norm, 1e-3);
  EXPECT_NE(unreachable.describe().find("5-joint"), std::string::npos) << unreachable.describe();
  EXPECT_TRUE(q.allFinite());

  // Six joints, a pose 5 m away: the arm stretches towards it and stops short.
  const auto ur5 = make_ur5();
  const SerialArm& six = arm_of(*ur5);
  const VectorXd ur5_params = ur5->parameters().nominal_values().head(six.num_parameters());
  Pose far = six.home_pose();
  far.translation = Vector3d(5000, 0, 0);
  VectorXd q6(6);
  const auto not_converged = six.inverse_kinematics(ur5_params, far, q6);
  EXPECT_EQ(not_converged.status, InverseKinematicsStatus::kNotConverged)
      << not_converged.describe();
  EXPECT_GT(not_converged.residual_norm, 3000);
  EXPECT_TRUE(q6.allFinite());

  Pose nan_pose = far;
  nan_pose.translation.x() = std::nan("");
  EXPECT_EQ(six.inverse_kinematics(ur5_params, nan_pose, q6).status,
            InverseKinematicsStatus::kNonFinite);
  EXPECT_TRUE(q6.allFinite());
}

TEST(SerialArm, ForwardKinematicsFailsOnlyOnNonFiniteInput) {
  const SerialArm arm(mixed_arm());
  VectorXd params = serial_arm_parameters(mixed_arm());
  VectorXd q = VectorXd::Constant(5, 0.3);
  EXPECT_TRUE(arm.forward_kinematics(params, q, Pose{}).ok());
  q[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(arm.forward_kinematics(params, q, Pose{}).status,
            ForwardKinematicsStatus::kInvalidActuators);
  q[2] = 0.3;
  params[SerialArm::joint_index(3) + SerialArm::kA] = std::nan("");
  const auto fk = arm.forward_kinematics(params, q, Pose{});
  EXPECT_EQ(fk.status, ForwardKinematicsStatus::kNonFinite);
  EXPECT_TRUE(fk.pose.translation.allFinite());
}

TEST(SerialArm, RejectsGeometriesItCannotRepresent) {
  SerialArmGeometry g = mixed_arm();
  g.joints[2].convention = LinkConvention::kHayati;  // the prismatic joint
  EXPECT_THROW(SerialArm{g}, std::invalid_argument);
  g = mixed_arm();
  g.joints[3].name = "j1";
  EXPECT_THROW(SerialArm{g}, std::invalid_argument);
  g = mixed_arm();
  g.joints[0].name = "tool";
  EXPECT_THROW(SerialArm{g}, std::invalid_argument);
  EXPECT_THROW(SerialArm{SerialArmGeometry{}}, std::invalid_argument);
}

// --- calibration with the trackers ---

TEST(SerialArmCalibration, PoseTrackerReadingsMissingInSomeConfigurationsStillDetermineAll) {
  // The ur5's camera lost the marker in a third of the configurations (NaN readings): the 20
  // left (120 readings for 30 parameters) still determine every parameter exactly.
  ScenarioOptions options;
  options.num_validation = 0;
  Scenario s = make_scenario(make_ur5(), options);
  for (int j = 0; j < s.calibration.size(); j += 3) s.calibration.readings.row(j).setConstant(NAN);
  const auto solver = SolverRegistry::global().create("lm");
  const CalibrationRun run = run_calibration(s, *solver, SolverOptions{}, false);
  ASSERT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.message;
  for (int i : s.free_indices)
    EXPECT_NEAR(run.estimate[i], s.truth[i], 1e-8) << s.model->parameters()[i].name;
}

TEST(SerialArmCalibration, NoisyPointTrackerEstimatesLieWithinTheirStandardDeviations) {
  // 0.05 mm tracker noise, 100 configurations: every estimate of the puma560's 27 parameters
  // is within 4 of its reported standard deviations of the truth, and the noise estimate
  // matches the simulated one (uniform: a / sqrt(3)).
  ScenarioOptions options;
  options.num_validation = 0;
  options.num_configurations = 100;
  options.noise_half_width.set(kincal::kMillimetre, 0.05);
  options.seed = 7;
  const Scenario s = make_scenario(make_puma560(), options);
  const auto solver = SolverRegistry::global().create("lm");
  const CalibrationRun run = run_calibration(s, *solver, SolverOptions{}, false);
  ASSERT_EQ(run.summary.termination, TerminationType::kConverged) << run.summary.message;
  CalibrationProblem problem(s.model, s.calibration, run.estimate, s.free_indices);
  VectorXd r;
  MatrixXd J;
  std::string why;
  ASSERT_TRUE(problem.evaluate(problem.initial_free_parameters(), &r, &J, &why)) << why;
  const ParameterUncertainty u = estimate_uncertainty(J, r);
  EXPECT_NEAR(u.sigma, 0.05 / std::sqrt(3.0), 0.1 * 0.05 / std::sqrt(3.0));
  double worst = 0;
  for (std::size_t k = 0; k < s.free_indices.size(); ++k) {
    const int i = s.free_indices[k];
    const double z = std::abs(run.estimate[i] - s.truth[i]) / u.std[static_cast<int>(k)];
    EXPECT_LT(z, 4) << s.model->parameters()[i].name;
    worst = std::max(worst, z);
  }
  std::printf("sigma %.4g mm (simulated %.4g), worst |error| / std %.2f\n", u.sigma,
              0.05 / std::sqrt(3.0), worst);
}

// --- model files ---

Json arm_json(const SerialArm& arm) {
  return ModelRegistry::global()
      .mechanism("serial-arm")
      .write(arm, serial_arm_parameters(arm.nominal_geometry()));
}

std::string read_error(const Json& mechanism) {
  try {
    ModelRegistry::global()
        .mechanism("serial-arm")
        .read(mechanism, JsonPath("arm.json", "mechanism"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SerialArmFile, RoundTripsEveryKindOfJoint) {
  SerialArmGeometry g = mixed_arm();
  g.joints[0].home = 0.25;
  g.joints[2].home = 30;
  g.joints[2].range = 80;
  g.joints[4].range = 0.2;
  const SerialArm arm(g);
  const Json j = arm_json(arm);
  EXPECT_EQ(j["joints"][2]["type"], "prismatic");
  EXPECT_EQ(j["joints"][1]["convention"], "hayati");
  EXPECT_TRUE(j["joints"][1].contains("beta_deg"));
  EXPECT_FALSE(j["joints"][1].contains("d"));
  EXPECT_EQ(j["joints"][2]["range"], 80.0);
  EXPECT_FALSE(j["joints"][0].contains("range_deg"));  // the default is not written
  Json with_type = j;
  with_type["type"] = "serial-arm";
  const auto back = ModelRegistry::global().mechanism("serial-arm").read(with_type, JsonPath("a"));
  const auto& arm2 = dynamic_cast<const SerialArm&>(*back);
  EXPECT_EQ(arm_json(arm2).dump(), j.dump());
  EXPECT_LT((serial_arm_parameters(arm2.nominal_geometry()) - serial_arm_parameters(g)).norm(),
            1e-12);
  // Calibrated values give a geometry whose parameters are those values.
  VectorXd calibrated = serial_arm_parameters(g);
  calibrated.array() += 0.01;
  EXPECT_EQ(serial_arm_parameters(arm.geometry_from(calibrated)), calibrated);
  VectorXd home(5);
  arm2.home_actuators(serial_arm_parameters(g), home);
  EXPECT_NEAR(home[0], 0.25, 1e-15);
  EXPECT_NEAR(home[2], 30, 1e-15);
  EXPECT_NEAR(arm2.actuators()[4].default_range, 0.2, 1e-15);
  EXPECT_EQ(arm2.actuators()[2].default_range, 80);
}

TEST(SerialArmFile, ErrorsNameTheFieldAndWhatWasExpected) {
  SerialArmGeometry g = mixed_arm();
  Json good = arm_json(SerialArm(g));
  good["type"] = "serial-arm";
  auto edited = [&](const std::function<void(Json&)>& edit) {
    Json j = good;
    edit(j);
    return read_error(j);
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {edited([](Json& j) { j["joints"][1]["d"] = 0; }),
       "arm.json: mechanism.joints[1].d: a Hayati link has no d"},
      {edited([](Json& j) { j["joints"][0]["beta_deg"] = 0; }),
       "arm.json: mechanism.joints[0].beta_deg: a DH link has no beta"},
      {edited([](Json& j) { j["joints"][2]["convention"] = "hayati"; }),
       "arm.json: mechanism.joints[2].convention: expected \"dh\" for a prismatic joint"},
      {edited([](Json& j) { j["joints"][0]["home"] = 1; }),
       "arm.json: mechanism.joints[0].home: a revolute joint's angles are in degrees: expected "
       "home_deg"},
      {edited([](Json& j) { j["joints"][2]["range_deg"] = 1; }),
       "arm.json: mechanism.joints[2].range_deg: a prismatic joint moves in mm: expected "
       "\"range\""},
      {edited([](Json& j) { j["joints"][3].erase("a"); }),
       "arm.json: mechanism.joints[3]: missing key 'a'"},
      {edited([](Json& j) { j["joints"][3]["alpha_deg"] = "90"; }),
       "arm.json: mechanism.joints[3].alpha_deg: expected a number"},
      {edited([](Json& j) { j["joints"][3]["type"] = "spherical"; }),
       "arm.json: mechanism.joints[3].type: expected \"revolute\" or \"prismatic\""},
      {edited([](Json& j) { j["joints"][3]["convention"] = "mdh"; }),
       "arm.json: mechanism.joints[3].convention: expected \"dh\" or \"hayati\""},
      {edited([](Json& j) { j["joints"][3]["name"] = "j1"; }),
       "arm.json: mechanism.joints[3].name: 'j1' is the name of an earlier joint"},
      {edited([](Json& j) { j["joints"][0]["name"] = "base"; }),
       "arm.json: mechanism.joints[0].name: 'base' names the arm's base frame"},
      {edited([](Json& j) { j["joints"][4]["range_deg"] = 0; }),
       "arm.json: mechanism.joints[4].range_deg: expected a half-width > 0"},
      {edited([](Json& j) { j["joints"][4]["lenght"] = 0; }),
       "arm.json: mechanism.joints[4]: unknown key 'lenght'"},
      {edited([](Json& j) { j["joints"] = Json::array(); }),
       "arm.json: mechanism.joints: expected a non-empty array of joint objects"},
      {edited([](Json& j) { j["tool"].erase("position"); }),
       "arm.json: mechanism.tool: missing key 'position'"},
  };
  for (const auto& [error, expected] : cases)
    EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
}

}  // namespace
}  // namespace kincal
