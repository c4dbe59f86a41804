// Joint compliance under gravity (models/joint_compliance.hpp, the urdf-arm's compliance):
//   - the gravity torques against an independent computation: minus the derivative of the
//     arm's potential energy (sum of m g h over its links' centres of mass) by each joint;
//   - forward kinematics with compliance is the rigid arm at the deflected joints;
//   - the conformance suite on the fitted-masses variant (the given-masses one is the preset
//     ur5-urdf-compliance, checked with every preset): Jacobians against finite differences,
//     model file round trip, recovery with every backend;
//   - efficiency: simulated compliances, with payloads varying per row, scatter as the
//     reported uncertainty (the Cramér-Rao bound of the linearised problem) says, with the
//     URDF's masses and with fitted moments;
//   - the model file's compliance section: read back exactly, errors that name the key.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "kincal/framework/analysis/calibration_report.hpp"
#include "kincal/framework/analysis/identifiability.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/random.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/conformance.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "kincal/models/urdf_io.hpp"

namespace kincal {
namespace {

const UrdfArm& arm_of(const MeasurementModel& model) {
  return dynamic_cast<const UrdfArm&>(model.mechanism());
}

// The UR5 of the preset ur5-urdf with fitted moments (no masses known) and a payload column.
std::shared_ptr<MeasurementModel> fitted_ur5() {
  auto preset = make_preset("ur5-urdf-compliance");
  UrdfArmGeometry g = arm_of(*preset).nominal_geometry();
  g.compliance.masses = GravityMasses::kFitted;
  g.compliance.links.clear();
  g.compliance.values = {{"shoulder_lift_joint.moment.elbow_joint", 2e-4},
                         {"shoulder_lift_joint.moment.tip", 1e-4},
                         {"elbow_joint.moment.tip", 1.5e-4},
                         {"shoulder_lift_joint.compliance", 1e-5},
                         {"elbow_joint.compliance", 1e-5}};
  auto arm = std::make_shared<UrdfArm>(g);
  auto model = std::make_shared<MeasurementModel>(arm, preset->sensors());
  free_what_home_configurations_determine(*model, 1.7, 2.3, 0.1);
  // Gravity's tilt stays fixed: with a moment per pair of joints the data determine it only
  // through products with the moments, so weakly that the estimates' scatter is 15 times
  // what the linearised uncertainty says (measured here with it free).
  model->parameters().set_free("gravity.*", false);
  return model;
}

void expect_all_pass(const std::vector<ConformanceCheck>& checks) {
  ASSERT_FALSE(checks.empty()) << "no check ran";
  for (const auto& c : checks)
    EXPECT_TRUE(c.passed) << c.name << ": worst " << c.worst << " (tolerance " << c.tolerance
                          << "), " << c.detail;
}

// The UR5 as a DH arm (the serial-arm type; UR's table, Hayati links for the parallel axes)
// with UR's published masses and centres of mass in its DH frames, a payload column and a
// point tracker; free: what 30 configurations around home determine.
std::shared_ptr<MeasurementModel> dh_ur5(GravityMasses masses = GravityMasses::kGiven) {
  auto joint = [](const std::string& name, double a, double alpha_deg, double d, double home_deg,
                  bool hayati) {
    SerialJoint j;
    j.name = name;
    j.a = a;
    j.alpha = alpha_deg * kPi / 180;
    j.d = d;
    j.home = home_deg * kPi / 180;
    if (hayati) j.convention = LinkConvention::kHayati;
    return j;
  };
  SerialArmGeometry g;
  g.joints = {joint("j1", 0, 90, 89.159, 0, false),   joint("j2", -425, 0, 0, -90, true),
              joint("j3", -392.25, 0, 0, 90, true),   joint("j4", 0, 90, 109.15, -90, false),
              joint("j5", 0, -90, 94.65, -90, false), joint("j6", 0, 0, 82.3, 0, false)};
  ComplianceSpec& c = g.compliance;
  c.enabled = true;
  c.masses = masses;
  if (masses == GravityMasses::kGiven)
    c.links = {{3.7, Vector3d(0, -25.61, 1.93)}, {8.393, Vector3d(212.5, 0, 113.36)},
               {2.275, Vector3d(150, 0, 26.5)},  {1.219, Vector3d(0, -1.8, 16.34)},
               {1.219, Vector3d(0, 1.8, 16.34)}, {0.1879, Vector3d(0, 0, -1.159)}};
  c.payload_column = true;
  c.payload.centre = Vector3d(0, 0, 50);
  for (const char* name : {"j2", "j3", "j4", "j5"})
    c.values.emplace_back(std::string(name) + ".compliance", 2e-5);
  auto arm = std::make_shared<SerialArm>(g);
  auto tracker = std::make_shared<PointTracker>("tracker", Vector6d::Zero(), Vector3d(40, 30, 50));
  auto model =
      std::make_shared<MeasurementModel>(arm, std::vector<std::shared_ptr<const Sensor>>{tracker});
  const VectorXd nominal = model->parameters().nominal_values();
  VectorXd home(7), readings(3);
  arm->home_actuators(nominal, home);
  auto ws = model->make_workspace();
  MatrixXd J(90, model->num_parameters()), block(3, model->num_parameters());
  for (int k = 0; k < 30; ++k) {
    VectorXd q = home;
    for (int i = 0; i < 6; ++i) q[i] += 0.5 * std::sin(1.7 * k + 2.3 * i + 0.1 * k * i);
    q[6] = 2.5 + 2.5 * std::sin(0.9 * k);
    Eigen::Ref<MatrixXd> ref(block);
    model->predict(nominal, q, readings, &ref, ws);
    J.middleRows(3 * k, 3) = block;
  }
  for (int i : identifiable_subset(J, model->identification_priority()))
    model->parameters().set_free(model->parameters()[i].name, true);
  model->parameters().set_free("gravity.*", false);
  return model;
}

TEST(GravityTorques, TheDhArmAndTheUrdfArmAgreeOnTheUr5) {
  // Two chains (DH frames, the URDF's link frames) and two sources of the same masses (UR's
  // table, the URDF's inertials moved into its link frames): the same torques.
  const auto dh = dh_ur5();
  const auto urdf = make_preset("ur5-urdf-compliance");
  const auto& dh_arm = dynamic_cast<const SerialArm&>(dh->mechanism());
  const UrdfArm& urdf_arm = arm_of(*urdf);
  VectorXd unit_dh = dh->parameters().nominal_values();
  VectorXd unit_urdf = urdf->parameters().nominal_values();
  for (int i = 0; i < 6; ++i) {
    unit_dh[dh_arm.compliance_index() + 2 + i] = 1;
    unit_urdf[urdf_arm.compliance_index() + 2 + i] = 1;
  }
  Random rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    VectorXd q(7);
    for (int i = 0; i < 6; ++i) q[i] = rng.symmetric(3.0);
    q[6] = 3 * rng.uniform01();
    GravityChain a, b;
    dh_arm.gravity_chain(q, a);
    urdf_arm.gravity_chain(q, b);
    JointVector tau_dh, tau_urdf;
    dh_arm.compliance().deflections(a, unit_dh.data() + dh_arm.compliance_index(), q[6], tau_dh,
                                    nullptr);
    urdf_arm.compliance().deflections(b, unit_urdf.data() + urdf_arm.compliance_index(), q[6],
                                      tau_urdf, nullptr);
    EXPECT_LT((tau_dh - tau_urdf).norm(), 1e-9 * (1 + tau_urdf.norm())) << trial;
    EXPECT_GT(tau_urdf.norm(), 1.0);
  }
}

TEST(JointCompliance, TheDhArmPassesTheConformanceSuite) {
  for (GravityMasses masses : {GravityMasses::kGiven, GravityMasses::kFitted}) {
    const auto model = dh_ur5(masses);
    int free_compliance = 0;
    for (const Parameter& p : model->parameters().all())
      free_compliance += p.free && (p.unit == "rad/Nm" || p.unit == "rad/m");
    EXPECT_GE(free_compliance, 3) << to_string(masses);
    expect_all_pass(check_model([masses] { return dh_ur5(masses); }, SolverRegistry::global()));
  }
}

// The potential energy of the links' and the payload's weights at q, J (m g h, h along -g).
double potential_energy(const UrdfArm& arm, const VectorXd& q) {
  GravityChain chain;
  arm.gravity_chain(q, chain);
  const ComplianceSpec& c = arm.nominal_geometry().compliance;
  const Vector3d up = -c.gravity.normalized();
  double energy = 0;
  for (int i = 0; i < chain.joints; ++i) {
    const PointMass& m = c.links[static_cast<std::size_t>(i)];
    const Vector3d p = chain.link[i].rotation * m.centre + chain.link[i].translation;
    energy += m.mass * kStandardGravity * up.dot(p) / 1000.0;
  }
  const Vector3d p = chain.tip.rotation * c.payload.centre + chain.tip.translation;
  energy += q[chain.joints] * kStandardGravity * up.dot(p) / 1000.0;
  return energy;
}

TEST(GravityTorques, AreMinusThePotentialEnergysDerivative) {
  auto model = make_preset("ur5-urdf-compliance");
  const UrdfArm& arm = arm_of(*model);
  const int n = arm.num_joints();
  // Unit compliances: the deflection is the torque itself.
  VectorXd params = model->parameters().nominal_values();
  for (int i = 0; i < n; ++i) params[arm.compliance_index() + 2 + i] = 1.0;
  Random rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    VectorXd q(n + 1);
    for (int i = 0; i < n; ++i) q[i] = rng.symmetric(3.0);
    q[n] = rng.uniform01() * 5;  // payload, kg
    GravityChain chain;
    arm.gravity_chain(q, chain);
    JointVector tau;
    arm.compliance().deflections(chain, params.data() + arm.compliance_index(), q[n], tau, nullptr);
    for (int i = 0; i < n; ++i) {
      const double h = 1e-6;
      VectorXd up = q, down = q;
      up[i] += h;
      down[i] -= h;
      const double expected = -(potential_energy(arm, up) - potential_energy(arm, down)) / (2 * h);
      EXPECT_NEAR(tau[i], expected, 1e-6 * (1 + std::abs(expected))) << "joint " << i;
    }
  }
}

TEST(JointCompliance, ForwardKinematicsIsTheRigidArmAtTheDeflectedJoints) {
  auto model = make_preset("ur5-urdf-compliance");
  const UrdfArm& arm = arm_of(*model);
  UrdfArmGeometry rigid_geometry = arm.nominal_geometry();
  rigid_geometry.compliance = ComplianceSpec{};
  const UrdfArm rigid(rigid_geometry);
  const VectorXd params = model->parameters().nominal_values();
  const VectorXd rigid_params = params.head(rigid.num_parameters());
  VectorXd q(7);
  q << 0.3, -1.2, 1.4, -1.6, -1.5, 0.2, 4.0;
  JointVector deflected;
  arm.deflected_joints(params, q, deflected);
  const VectorXd delta = deflected - q.head(6);
  // The UR5's shoulder at 1e-5 rad/Nm under its arm and 4 kg: tens of microradians.
  EXPECT_GT(std::abs(delta[1]), 1e-4);
  EXPECT_EQ(delta[0], 0.0);  // gravity along the pan axis: no torque
  const Pose with = arm.forward_kinematics(params, q, Pose{}).pose;
  const Pose without = rigid.forward_kinematics(rigid_params, VectorXd(deflected), Pose{}).pose;
  EXPECT_LT((with.translation - without.translation).norm(), 1e-12);
  EXPECT_LT((with.rotation - without.rotation).norm(), 1e-14);
  // And a payload moves the tool: 1 kg more, a visible change.
  VectorXd heavier = q;
  heavier[6] += 1;
  EXPECT_GT(
      (arm.forward_kinematics(params, heavier, Pose{}).pose.translation - with.translation).norm(),
      1e-3);
}

TEST(JointCompliance, FittedMomentsPassTheConformanceSuite) {
  const auto model = fitted_ur5();
  int moments_free = 0;
  for (const Parameter& p : model->parameters().all())
    if (p.free && p.name.find(".moment.") != std::string::npos) ++moments_free;
  EXPECT_GE(moments_free, 3);
  expect_all_pass(check_model([] { return fitted_ur5(); }, SolverRegistry::global()));
}

TEST(JointCompliance, ModelFileRoundTripsAndNamesBadKeys) {
  const auto model = fitted_ur5();
  const VectorXd values = model->parameters().nominal_values();
  const auto text = model_to_json(*model, values).dump(2);
  const auto back = model_from_text(text, "m.json");
  EXPECT_EQ(back->parameters().nominal_values(), values);
  ASSERT_EQ(back->num_parameters(), model->num_parameters());
  for (int i = 0; i < model->num_parameters(); ++i)
    EXPECT_EQ(back->parameters()[i].free, model->parameters()[i].free);

  auto j = nlohmann::ordered_json::parse(text);
  j["mechanism"]["compliance"]["values"]["elbow_joint.moment.nowhere"] = 1;
  try {
    model_from_json(j, "m.json");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("elbow_joint.moment.nowhere"), std::string::npos)
        << e.what();
  }
  j = nlohmann::ordered_json::parse(text);
  j["mechanism"]["compliance"]["masses"] = "given";
  try {
    model_from_json(j, "m.json");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.compliance.links"), std::string::npos)
        << e.what();
  }
}

TEST(JointCompliance, ImportedFromTheUrdfWithItsInertials) {
  UrdfModelOptions options;
  options.tip_link = "flange";
  options.compliance = UrdfCompliance::kAuto;
  const auto model = model_from_urdf(ur5_urdf_text(), "ur5.urdf", options);
  const ComplianceSpec& c = arm_of(*model).nominal_geometry().compliance;
  ASSERT_EQ(c.masses, GravityMasses::kGiven);
  ASSERT_EQ(c.links.size(), 6u);
  EXPECT_DOUBLE_EQ(c.links[1].mass, 8.393);
  EXPECT_NEAR(c.links[1].centre.x(), -212.5, 1e-9);
  EXPECT_NEAR(c.links[1].centre.z(), 113.36, 1e-9);
  // The flange link has no inertial; wrist 3's own is its child link's.
  EXPECT_DOUBLE_EQ(c.links[5].mass, 0.1879);
  EXPECT_FALSE(model->parameters()[model->parameters().index_of("gravity.rx")].free);
  EXPECT_TRUE(model->parameters()[model->parameters().index_of("elbow_joint.compliance")].free);

  // Without inertials, "urdf" masses are an error and auto falls back to fitted moments.
  std::string bare = ur5_urdf_text();
  for (std::size_t at; (at = bare.find("<inertial>")) != std::string::npos;)
    bare.erase(at, bare.find("</inertial>", at) + 11 - at);
  options.compliance = UrdfCompliance::kInertials;
  EXPECT_THROW(model_from_urdf(bare, "bare.urdf", options), std::invalid_argument);
  options.compliance = UrdfCompliance::kAuto;
  const auto fitted = model_from_urdf(bare, "bare.urdf", options);
  EXPECT_EQ(arm_of(*fitted).nominal_geometry().compliance.masses, GravityMasses::kFitted);
}

// Efficiency: 60 noise draws of 60 configurations with payloads of 0 to 5 kg; the scatter of
// every free parameter (the compliances included) against the reported std.
void expect_efficient(std::shared_ptr<MeasurementModel> model, const char* label) {
  ScenarioOptions options;
  options.num_configurations = 60;
  options.num_validation = 0;
  options.seed = 11;
  const Scenario exact = make_scenario(model, options);
  const auto solver = SolverRegistry::global().create("lm");
  const double sigma = 0.01, a = sigma * std::sqrt(3.0);  // mm, uniform
  const int trials = 60;
  const int n = static_cast<int>(exact.free_indices.size());
  MatrixXd estimates(trials, n);
  VectorXd reported = VectorXd::Zero(n);
  Random rng(5);
  for (int t = 0; t < trials; ++t) {
    Measurements data = exact.calibration;
    for (Eigen::Index j = 0; j < data.readings.size(); ++j)
      data.readings.data()[j] += rng.symmetric(a);
    CalibrationProblem problem(exact.model, data, exact.nominal, exact.free_indices);
    VectorXd x = problem.initial_free_parameters();
    const Summary summary = solver->solve(problem, x, SolverOptions{});
    ASSERT_TRUE(summary.converged()) << summary.message;
    const CalibrationReport report = make_calibration_report(problem, x, summary, {});
    estimates.row(t) = x.transpose();
    reported += report.uncertainty.std / trials;
  }
  int compliances = 0;
  double worst = 1;
  for (int i = 0; i < n; ++i) {
    const std::string& name = exact.model->parameters()[exact.free_indices[i]].name;
    const VectorXd column = estimates.col(i);
    const double mean = column.mean();
    const double spread = std::sqrt((column.array() - mean).square().sum() / (trials - 1));
    EXPECT_NEAR(spread / reported[i], 1.0, 0.32) << label << " " << name;
    EXPECT_NEAR(mean, exact.truth[exact.free_indices[i]], 4 * spread / std::sqrt(double(trials)))
        << label << " " << name;
    if (name.find(".compliance") != std::string::npos ||
        name.find(".moment.") != std::string::npos) {
      ++compliances;
      if (std::abs(spread / reported[i] - 1) > std::abs(worst - 1)) worst = spread / reported[i];
      std::printf("%s: %-40s truth %+.4g  mean %+.4g  scatter %.3g  reported %.3g\n", label,
                  name.c_str(), exact.truth[exact.free_indices[i]], mean, spread, reported[i]);
    }
  }
  EXPECT_GE(compliances, 3) << label;
  std::printf("%s: %d free, %d compliance terms, worst scatter / reported %.3f\n", label, n,
              compliances, worst);
}

TEST(JointComplianceEfficiency, GivenMassesWithPayloads) {
  expect_efficient(make_preset("ur5-urdf-compliance"), "given masses");
}

TEST(JointComplianceEfficiency, FittedMomentsWithPayloads) {
  expect_efficient(fitted_ur5(), "fitted moments");
}

}  // namespace
}  // namespace kincal
