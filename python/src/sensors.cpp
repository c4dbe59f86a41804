// Sensors written in Python (prototypes): a kincal.Sensor subclass gives its readings and
// their Jacobians in numpy; PythonSensor makes it a C++ Sensor, so that simulation,
// calibration and every backend use it as a built-in one (slow path: each prediction takes
// the GIL). check_sensors holds it to the finite-difference checks every registered sensor
// passes, kincal's own (models/conformance.hpp, as `kincal check`: central differences, step
// 1e-6, |analytic - numeric| <= 1e-6 (1 + |numeric|) entrywise).

#include <pybind11/stl.h>

#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/models/conformance.hpp"
#include "model_handle.hpp"
#include "python_mechanism.hpp"

namespace kincal::python {

namespace {

class PythonSensor : public Sensor {
 public:
  explicit PythonSensor(py::object impl) : impl_(std::move(impl)) {
    type_ = impl_.attr("type").cast<std::string>();
    name_ = impl_.attr("name").cast<std::string>();
    reading_names_ = impl_.attr("reading_names").cast<std::vector<std::string>>();
    reading_units_ = impl_.attr("reading_units").cast<std::vector<std::string>>();
    position_index_ = impl_.attr("position_reading_index").cast<int>();
    if (reading_names_.empty() || reading_names_.size() != reading_units_.size())
      throw py::value_error("sensor " + name_ +
                            ": reading_names and reading_units: expected one unit per reading");
    for (const auto& u : reading_units_)
      if (u != "mm" && u != "rad")
        throw py::value_error("sensor " + name_ + ": reading unit '" + u +
                              "': expected 'mm' or 'rad'");
    for (const auto& p : impl_.attr("parameters").cast<py::list>()) {
      const auto t = p.cast<py::tuple>();
      if (t.size() != 3)
        throw py::value_error("sensor " + name_ +
                              ": parameters: expected (name, nominal, unit) tuples");
      Parameter param;
      param.name = t[0].cast<std::string>();
      param.nominal = t[1].cast<double>();
      param.unit = t[2].cast<std::string>();
      if (param.unit != "mm" && param.unit != "rad")
        throw py::value_error("sensor " + name_ + ": parameter " + param.name + ": unit '" +
                              param.unit + "': expected 'mm' or 'rad'");
      parameters_.push_back(param);
    }
  }
  ~PythonSensor() override {
    py::gil_scoped_acquire acquire;
    impl_ = py::object();
  }

  std::string type() const override { return type_; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return static_cast<int>(reading_names_.size()); }
  std::vector<std::string> reading_names() const override { return reading_names_; }
  std::vector<std::string> reading_units() const override { return reading_units_; }
  int position_reading_index() const override { return position_index_; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }

  // A Python error cannot cross the solvers (they are noexcept about numerics): the first
  // one is kept, the readings become NaN (the residuals "not computable"), and the caller
  // rethrows it when the solve returns.
  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override {
    py::gil_scoped_acquire acquire;
    const int n = num_readings(), p = num_parameters();
    try {
      const py::object out =
          impl_.attr("predict")(to_numpy(VectorXd(params)), to_numpy(VectorXd(pose.translation)),
                                to_numpy(MatrixXd(pose.rotation)),
                                J_reading_pose != nullptr || J_reading_params != nullptr);
      const auto t = out.cast<py::tuple>();
      if (t.size() != 3)
        throw py::value_error(name_ + ".predict: expected (reading, J_pose, J_params)");
      const auto r = as_vector(t[0], (name_ + ".predict reading").c_str(), n);
      reading = Eigen::Map<const VectorXd>(r.data(), n);
      if (J_reading_pose) *J_reading_pose = jacobian(t[1], "J_pose", n, 6);
      if (J_reading_params) *J_reading_params = jacobian(t[2], "J_params", n, p);
    } catch (...) {
      remember(std::current_exception());
      reading.setConstant(std::numeric_limits<double>::quiet_NaN());
      if (J_reading_pose) J_reading_pose->setZero();
      if (J_reading_params) J_reading_params->setZero();
    }
  }

  void rethrow() const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) {
      std::exception_ptr e = error_;
      error_ = nullptr;
      std::rethrow_exception(e);
    }
  }

 private:
  MatrixXd jacobian(const py::handle& value, const std::string& what, int rows, int cols) const {
    const std::string argument = name_ + ".predict " + what;
    if (cols == 0) return MatrixXd(rows, 0);
    const auto a = as_rows(value, argument.c_str(), cols);
    if (a.shape(0) != rows)
      throw py::value_error(argument + ": expected shape (" + std::to_string(rows) + ", " +
                            std::to_string(cols) + "), got (" + std::to_string(a.shape(0)) + ", " +
                            std::to_string(cols) + ")");
    return rows_view(a);
  }
  void remember(std::exception_ptr e) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = e;
  }

  py::object impl_;
  std::string type_, name_;
  std::vector<std::string> reading_names_, reading_units_;
  int position_index_ = -1;
  std::vector<Parameter> parameters_;
  mutable std::mutex mutex_;
  mutable std::exception_ptr error_;
};

}  // namespace

void rethrow_python_errors(const MeasurementModel& model) {
  if (const auto* mechanism = dynamic_cast<const PythonMechanism*>(&model.mechanism()))
    mechanism->rethrow();
  for (const auto& s : model.sensors())
    if (const auto* py_sensor = dynamic_cast<const PythonSensor*>(s.get())) py_sensor->rethrow();
}

namespace {

// A model of a Python mechanism and Python sensors; every parameter free that the mechanism
// marks free, and every sensor parameter.
ModelHandle python_model(const py::object& mechanism, const py::list& sensors) {
  auto mech = std::make_shared<PythonMechanism>(mechanism);
  std::vector<std::shared_ptr<const Sensor>> list;
  for (const auto& s : sensors)
    list.push_back(std::make_shared<PythonSensor>(py::reinterpret_borrow<py::object>(s)));
  auto model = std::make_shared<MeasurementModel>(mech, list);
  ParameterSet& to = model->parameters();
  for (int i = mech->num_parameters(); i < to.size(); ++i) to.set_free(to[i].name, true);
  return {model, "Python mechanism " + mech->type()};
}

// `base`'s mechanism with `sensors` (Python sensors or the base model's own, by name).
ModelHandle with_sensors(const ModelHandle& base, const py::list& sensors) {
  std::vector<std::shared_ptr<const Sensor>> list;
  for (const auto& s : sensors)
    list.push_back(std::make_shared<PythonSensor>(py::reinterpret_borrow<py::object>(s)));
  auto model = std::make_shared<MeasurementModel>(base.model->mechanism_ptr(), list);
  // The mechanism's free mask and values as in `base`; the sensors' parameters free.
  const ParameterSet& from = base.model->parameters();
  ParameterSet& to = model->parameters();
  const int mech = base.model->mechanism().num_parameters();
  for (int i = 0; i < mech; ++i) {
    to.for_each_matching(from[i].name, [&](Parameter& p) { p = from[i]; });
  }
  for (int i = mech; i < to.size(); ++i) to.set_free(to[i].name, true);
  for (int i = 0; i < model->mechanism().num_actuators(); ++i)
    model->set_actuator_range(model->mechanism().actuators()[i].name,
                              base.model->actuator_ranges()[i]);
  return {model, base.source + " with Python sensors"};
}

// kincal's own checks of a model's sensors and residual Jacobian (models/conformance.hpp,
// those of `kincal check`): the worst relative error of each kind, over every sensor.
py::dict check_sensors(const ModelHandle& h, std::uint64_t /*seed: kincal check's own*/) {
  std::vector<ConformanceCheck> checks;
  {
    py::gil_scoped_release release;
    const ModelFactory make = [&] { return std::make_shared<MeasurementModel>(*h.model); };
    checks = check_sensor_jacobians(make);
    for (const auto& c : check_residual_jacobian(make)) checks.push_back(c);
    rethrow_python_errors(*h.model);
  }
  double worst_params = 0, worst_pose = 0, worst_residuals = 0;
  for (const auto& c : checks) {
    // A check that could not run (e.g. forward kinematics failed) is a failure, not a pass.
    const double worst = c.passed || std::isfinite(c.worst) ? c.worst : INFINITY;
    if (!c.passed && !std::isfinite(c.worst))
      throw std::runtime_error("kincal.sensors.check: " + c.name + ": " + c.detail);
    if (c.name.rfind("J_reading_params", 0) == 0)
      worst_params = std::max(worst_params, worst);
    else if (c.name.rfind("J_reading_pose", 0) == 0)
      worst_pose = std::max(worst_pose, worst);
    else
      worst_residuals = std::max(worst_residuals, worst);
  }
  py::dict out;
  out["J_reading_params"] = worst_params;
  out["J_reading_pose"] = worst_pose;
  out["residual_jacobian"] = worst_residuals;
  out["tolerance"] = 1e-6;
  return out;
}

// A simulated calibration of any model (Python sensors included), solved directly: what
// `kincal simulate` does for a model file, for models no file can hold.
py::dict simulate_direct(const ModelHandle& h, int poses, double noise_mm, double noise_rad,
                         std::uint64_t seed, const std::string& solver_name, bool catch_sigint) {
  const std::unique_ptr<Solver> solver = SolverRegistry::global().create(solver_name);
  Scenario scenario;
  CalibrationRun run;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    ScenarioOptions o;
    o.num_configurations = poses;
    o.noise_half_width = UnitValues(noise_mm, noise_rad);
    o.seed = seed;
    o.num_validation = 50;
    scenario = make_scenario(h.model, o);
    rethrow_python_errors(*h.model);
    SigintScope sigint(catch_sigint);
    SolverOptions options;
    options.callback = [](const IterationRecord&, const VectorXd&) {
      return sigint_received() ? CallbackAction::kStop : CallbackAction::kContinue;
    };
    run = run_calibration(scenario, *solver, options, false);
    interrupted = sigint.interrupted();
    rethrow_python_errors(*h.model);
  }
  py::dict d;
  d["termination"] = std::string(to_string(run.summary.termination));
  d["message"] = run.summary.message;
  d["iterations"] = run.summary.iterations;
  d["estimate"] = to_numpy(run.estimate);
  d["truth"] = to_numpy(scenario.truth);
  d["nominal"] = to_numpy(scenario.nominal);
  d["free_indices"] = scenario.free_indices;
  d["actuators"] = to_numpy(scenario.calibration.actuators);
  d["readings"] = to_numpy(scenario.calibration.readings);
  d["parameter_rms_error_mm"] = run.parameter_rms_error;
  d["parameter_rms_error_rad"] = run.parameter_rms_error_rad;
  d["interrupted"] = interrupted;
  return d;
}

}  // namespace

void bind_sensors(py::module_& m) {
  m.def("_with_sensors", &with_sensors, py::arg("model"), py::arg("sensors"),
        "`model`'s mechanism (values and free mask) with these Python sensors, whose "
        "parameters are free.");
  m.def("_python_model", &python_model, py::arg("mechanism"), py::arg("sensors"),
        "A model of a Python mechanism (kincal.mechanisms.Mechanism) with Python sensors.");
  m.def("_check_sensors", &check_sensors, py::arg("model"), py::arg("seed") = 1,
        "Finite-difference checks of the model's sensors and residual Jacobian: worst "
        "relative errors (pass when each is <= tolerance).");
  m.def("_simulate_direct", &simulate_direct, py::arg("model"), py::arg("poses"),
        py::arg("noise_mm"), py::arg("noise_rad"), py::arg("seed"), py::arg("solver"),
        py::arg("catch_sigint"),
        "A simulated calibration of any model, solved in-process (kincal.sensors).");
}

}  // namespace kincal::python
