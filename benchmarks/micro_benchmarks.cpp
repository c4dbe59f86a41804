// kincal-micro-benchmarks (Google Benchmark): the per-configuration kernels, one full
// calibration of Table 2 case 5 per backend, and lm's scaling with the number of
// configurations. Targets and results: docs/benchmarks.md.

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/calibration/calibration_solve.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/serial_arm_presets.hpp"
#include "kincal/models/urdf_arm.hpp"
#include "tests/models/autodiff_twins.hpp"

namespace kincal {
namespace {

// Scenarios are expensive to draw for large m: drawn once per size and kept.
const Scenario& scenario_with(int num_configurations) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<Scenario>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[num_configurations];
  if (!slot) {
    ScenarioOptions o;
    o.num_configurations = num_configurations;
    o.noise_half_width.set(kincal::kMillimetre, paper_case(5).noise_half_width);
    o.num_validation = 0;
    o.seed = 1;
    slot = std::make_unique<Scenario>(make_scenario(make_cube_hexapod(), o));
  }
  return *slot;
}

const Scenario& case5() { return scenario_with(paper_case(5).num_configurations); }

// Case 5 with the hexapod and the gauge replaced by their automatic-derivative twins
// (tests/models/autodiff_twins.hpp): the same data, configurations and start.
const Scenario& case5_autodiff() {
  static const Scenario twin = [] {
    Scenario s = case5();
    s.model = testing::autodiff_twin(*s.model);
    return s;
  }();
  return twin;
}
const Scenario& case5_of(bool autodiff) { return autodiff ? case5_autodiff() : case5(); }

// A serial arm (PUMA 560, point tracker) as `kincal simulate --preset puma560` draws it.
const Scenario& puma560(bool autodiff) {
  static const Scenario hand = [] {
    ScenarioOptions o;
    o.num_configurations = 60;
    o.num_validation = 0;
    o.seed = 1;
    return make_scenario(make_puma560(), o);
  }();
  static const Scenario twin = [] {
    Scenario s = hand;
    s.model = testing::autodiff_twin(*s.model);
    return s;
  }();
  return autodiff ? twin : hand;
}

// The other two serial arms, drawn the same way: the UR5 (DH and Hayati links, pose tracker)
// and the UR5 imported from its URDF (6-DOF origin errors, point tracker). With the PUMA 560
// they time the serial-chain walk (models/serial_chain.hpp) under both link parametrisations.
const Scenario& serial_arm_scenario(const std::string& preset) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Scenario>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[preset];
  if (!slot) {
    ScenarioOptions o;
    o.num_configurations = 60;
    o.num_validation = 0;
    o.seed = 1;
    slot = std::make_unique<Scenario>(make_scenario(preset == "ur5" ? make_ur5()
                                                    : preset == "ur5-urdf"
                                                        ? make_ur5_urdf()
                                                        : make_ur5_urdf_compliance(),
                                                    o));
  }
  return *slot;
}

void BM_ForwardKinematics(benchmark::State& state) {
  const Scenario& s = case5();
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd truth = s.truth.head(mechanism.num_parameters());
  const auto& fk_options = s.model->forward_kinematics_options();
  int j = 0;
  double newton_steps = 0;
  for (auto _ : state) {
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        truth, s.calibration.actuators.row(j).transpose(), mechanism.home_pose(), fk_options);
    benchmark::DoNotOptimize(fk.pose.translation.data());
    newton_steps += fk.iterations;
    j = (j + 1) % s.calibration.size();
  }
  state.counters["newton_steps"] = newton_steps / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ForwardKinematics);

void BM_PredictWithJacobian(benchmark::State& state) {
  const Scenario& s = case5();
  const MeasurementModel& model = *s.model;
  auto ws = model.make_workspace();
  VectorXd readings(model.num_readings());
  MatrixXd J(model.num_readings(), model.num_parameters());
  Eigen::Ref<MatrixXd> J_ref(J);
  int j = 0;
  for (auto _ : state) {
    const auto fk =
        model.predict(s.nominal, s.calibration.actuators.row(j).transpose(), readings, &J_ref, ws);
    benchmark::DoNotOptimize(fk.iterations);
    benchmark::DoNotOptimize(J.data());
    j = (j + 1) % s.calibration.size();
  }
}
BENCHMARK(BM_PredictWithJacobian);

void BM_ResidualsAndJacobian(benchmark::State& state) {
  const Scenario& s = scenario_with(static_cast<int>(state.range(0)));
  const auto problem = s.make_problem();
  const VectorXd x = problem->initial_free_parameters();
  VectorXd r;
  MatrixXd J;
  for (auto _ : state) {
    if (!problem->evaluate(x, &r, &J)) state.SkipWithError("evaluation failed");
    benchmark::DoNotOptimize(J.data());
  }
}
BENCHMARK(BM_ResidualsAndJacobian)->Arg(60)->Unit(benchmark::kMicrosecond);

// Hand-written against automatic derivatives (docs/benchmarks.md): forward kinematics of one
// configuration with J_pose_params, on the hexapod of case 5 and on the PUMA 560.
void BM_MechanismWithJacobian(benchmark::State& state, const Scenario& s) {
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd truth = s.truth.head(mechanism.num_parameters());
  const auto& fk_options = s.model->forward_kinematics_options();
  Matrix6Xd J(6, mechanism.num_parameters());
  int j = 0;
  for (auto _ : state) {
    const ForwardKinematicsResult fk = mechanism.forward_kinematics(
        truth, s.calibration.actuators.row(j).transpose(), mechanism.home_pose(), fk_options);
    mechanism.pose_jacobian_params(truth, s.calibration.actuators.row(j).transpose(), fk.pose, J);
    benchmark::DoNotOptimize(J.data());
    j = (j + 1) % s.calibration.size();
  }
}
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, hexapod_hand, case5_of(false));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, hexapod_autodiff, case5_of(true));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, puma560_hand, puma560(false));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, puma560_autodiff, puma560(true));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, ur5_hand, serial_arm_scenario("ur5"));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, ur5_urdf_hand, serial_arm_scenario("ur5-urdf"));
BENCHMARK_CAPTURE(BM_MechanismWithJacobian, ur5_urdf_compliance,
                  serial_arm_scenario("ur5-urdf-compliance"));

// The whole per-configuration kernel of a calibration: forward kinematics, the readings and
// the reading Jacobian (adjoint form for the hexapod).
void BM_PredictWithJacobianOf(benchmark::State& state, const Scenario& s) {
  const MeasurementModel& model = *s.model;
  auto ws = model.make_workspace();
  VectorXd readings(model.num_readings());
  MatrixXd J(model.num_readings(), model.num_parameters());
  Eigen::Ref<MatrixXd> J_ref(J);
  int j = 0;
  for (auto _ : state) {
    const auto fk =
        model.predict(s.nominal, s.calibration.actuators.row(j).transpose(), readings, &J_ref, ws);
    benchmark::DoNotOptimize(fk.iterations);
    benchmark::DoNotOptimize(J.data());
    j = (j + 1) % s.calibration.size();
  }
}
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, hexapod_hand, case5_of(false));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, hexapod_autodiff, case5_of(true));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, puma560_hand, puma560(false));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, puma560_autodiff, puma560(true));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, ur5_hand, serial_arm_scenario("ur5"));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, ur5_urdf_hand, serial_arm_scenario("ur5-urdf"));
BENCHMARK_CAPTURE(BM_PredictWithJacobianOf, ur5_urdf_compliance,
                  serial_arm_scenario("ur5-urdf-compliance"));

// A serial arm's inverse kinematics from home (serial_chain::inverse_kinematics: forward
// kinematics and the joint Jacobian J_pose_q at every step) to the poses of the scenario's
// configurations. `ik_iterations` is the mean number of steps.
void BM_SerialInverseKinematics(benchmark::State& state, const Scenario& s) {
  const Mechanism& mechanism = s.model->mechanism();
  const VectorXd truth = s.truth.head(mechanism.num_parameters());
  std::vector<Pose> poses;
  for (Eigen::Index j = 0; j < s.calibration.actuators.rows(); ++j)
    poses.push_back(mechanism
                        .forward_kinematics(truth, s.calibration.actuators.row(j).transpose(),
                                            mechanism.home_pose())
                        .pose);
  VectorXd q(static_cast<Eigen::Index>(mechanism.actuators().size()));
  std::size_t j = 0;
  double iterations = 0;
  for (auto _ : state) {
    const InverseKinematicsResult ik = mechanism.inverse_kinematics(truth, poses[j], q);
    if (!ik.ok()) state.SkipWithError("inverse kinematics failed");
    benchmark::DoNotOptimize(q.data());
    iterations += ik.iterations;
    j = (j + 1) % poses.size();
  }
  state.counters["ik_iterations"] = iterations / static_cast<double>(state.iterations());
}
BENCHMARK_CAPTURE(BM_SerialInverseKinematics, puma560, puma560(false))
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SerialInverseKinematics, ur5, serial_arm_scenario("ur5"))
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SerialInverseKinematics, ur5_urdf, serial_arm_scenario("ur5-urdf"))
    ->Unit(benchmark::kMicrosecond);

SolverOptions calibration_options(const std::string& solver, int threads) {
  SolverOptions o;
  o.num_threads = threads;
  // NLopt counts objective evaluations against max_iterations.
  if (solver.rfind("nlopt:", 0) == 0) o.max_iterations = 2000;
  return o;
}

// A full calibration from nominal. Counters let the reader check that the backends reach the
// same solution: final cost, parameter RMS error against the truth, iterations.
void calibrate_scenario(benchmark::State& state, const Scenario& s, const std::string& name,
                        int threads, Formulation formulation = Formulation::kNested,
                        const std::map<std::string, std::string>& backend_options = {}) {
  const auto problem = s.make_problem();
  const auto solver = SolverRegistry::global().create(name);
  SolverOptions options = calibration_options(name, threads);
  options.backend = solver->parse_settings(backend_options);
  Summary summary;
  VectorXd x;
  for (auto _ : state) {
    x = problem->initial_free_parameters();
    CalibrationSolve solved =
        solve_calibration(*solver, *problem, Prior{}, x, options, formulation);
    if (!solved.note.empty()) state.SkipWithError(solved.note.c_str());
    summary = std::move(solved.summary);
    benchmark::DoNotOptimize(x.data());
  }
  const VectorXd error = x - problem->free_parameters(s.truth);
  state.counters["solver_iterations"] = summary.iterations;
  state.counters["final_cost"] = summary.final_cost;
  state.counters["param_rms_mm"] = std::sqrt(error.squaredNorm() / error.size());
  state.counters["converged"] = summary.converged() ? 1 : 0;
}

void calibrate(benchmark::State& state, const std::string& name, int num_configurations,
               int threads, Formulation formulation = Formulation::kNested,
               const std::map<std::string, std::string>& backend_options = {}) {
  calibrate_scenario(state, scenario_with(num_configurations), name, threads, formulation,
                     backend_options);
}

bool is_derivative_free(const std::string& name) { return name.rfind("nlopt:LN_", 0) == 0; }

void register_dynamic_benchmarks() {
  const SolverRegistry& registry = SolverRegistry::global();
  // Derivative-free NLopt needs thousands of evaluations: not a speed comparison.
  for (const std::string& name : registry.featured_names()) {
    if (is_derivative_free(name)) continue;
    benchmark::RegisterBenchmark(("BM_CalibrateCase5/" + name).c_str(), [name](
                                                                            benchmark::State& st) {
      calibrate(st, name, 60, 1);
    })->Unit(benchmark::kMillisecond);
  }
  if (registry.contains("lm")) {
    // lm on the implicit formulation (poses as unknowns, Schur complement), beside the nested
    // BM_CalibrateCase5/lm above: the same data and start.
    benchmark::RegisterBenchmark("BM_CalibrateCase5/lm/implicit", [](benchmark::State& st) {
      calibrate(st, "lm", 60, 1, Formulation::kImplicit);
    })->Unit(benchmark::kMillisecond);
    // Both with a trust region that opens at once: faster from nominal, but from far starts the
    // implicit solve then ends in another minimum on an eighth of the seeds
    // (docs/benchmarks.md, "Implicit formulation"): an option, not the default.
    for (const Formulation formulation : {Formulation::kNested, Formulation::kImplicit})
      benchmark::RegisterBenchmark(
          (std::string("BM_CalibrateCase5/lm/") +
           (formulation == Formulation::kImplicit ? "implicit/" : "") + "initial_trust_radius:1e8")
              .c_str(),
          [formulation](benchmark::State& st) {
            calibrate(st, "lm", 60, 1, formulation, {{"initial_trust_radius", "1e8"}});
          })
          ->Unit(benchmark::kMillisecond);
    // lm on case 5 with hand-written and with automatic derivatives, the same data.
    for (const bool autodiff : {false, true})
      benchmark::RegisterBenchmark(
          (std::string("BM_CalibrateCase5Derivatives/lm/") + (autodiff ? "autodiff" : "hand"))
              .c_str(),
          [autodiff](benchmark::State& st) { calibrate_scenario(st, case5_of(autodiff), "lm", 1); })
          ->Unit(benchmark::kMillisecond);
  }
  const std::string scaling_solver = registry.contains("lm") ? "lm" : "gn";
  for (int threads : {1, hardware_threads()}) {
    for (int m : {60, 600, 6000, 60000}) {
      benchmark::RegisterBenchmark(
          ("BM_Scaling/" + scaling_solver + "/m:" + std::to_string(m) +
           "/threads:" + std::to_string(threads))
              .c_str(),
          [=](benchmark::State& st) { calibrate(st, scaling_solver, m, threads); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      if (scaling_solver == "lm")
        benchmark::RegisterBenchmark(
            ("BM_Scaling/lm/implicit/m:" + std::to_string(m) +
             "/threads:" + std::to_string(threads))
                .c_str(),
            [=](benchmark::State& st) { calibrate(st, "lm", m, threads, Formulation::kImplicit); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    if (hardware_threads() == 1) break;
  }
}

}  // namespace
}  // namespace kincal

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  kincal::register_dynamic_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
