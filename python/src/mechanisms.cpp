// Mechanisms written in Python (python_mechanism.hpp), and kincal's own conformance checks of
// a model's mechanism Jacobians (models/conformance.hpp), the ones `kincal check` runs.

#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "kincal/models/conformance.hpp"
#include "model_handle.hpp"
#include "python_mechanism.hpp"

namespace kincal::python {

namespace {

std::string unit_of(const std::string& owner, const std::string& what, const std::string& unit) {
  if (unit != kMillimetre && unit != kRadian)
    throw py::value_error(owner + ": " + what + ": unit '" + unit + "': expected 'mm' or 'rad'");
  return unit;
}

Matrix6Xd six_rows(const py::handle& value, const std::string& argument, int cols) {
  if (cols == 0) return Matrix6Xd(6, 0);
  const auto a = as_rows(value, argument.c_str(), cols);
  if (a.shape(0) != 6)
    throw py::value_error(argument + ": expected shape (6, " + std::to_string(cols) + "), got (" +
                          std::to_string(a.shape(0)) + ", " + std::to_string(cols) + ")");
  return rows_view(a);
}

}  // namespace

PythonMechanism::PythonMechanism(py::object impl) : impl_(std::move(impl)) {
  type_ = impl_.attr("type").cast<std::string>();
  const std::string owner = "mechanism " + type_;
  for (const auto& a : impl_.attr("actuators").cast<py::list>()) {
    const auto t = a.cast<py::tuple>();
    if (t.size() != 3)
      throw py::value_error(owner + ": actuators: expected (name, unit, range) tuples");
    actuators_.push_back(
        {t[0].cast<std::string>(),
         unit_of(owner, "actuator " + t[0].cast<std::string>(), t[1].cast<std::string>()),
         t[2].cast<double>()});
  }
  for (const auto& p : impl_.attr("parameters").cast<py::list>()) {
    const auto t = p.cast<py::tuple>();
    if (t.size() != 3 && t.size() != 4)
      throw py::value_error(owner + ": parameters: expected (name, nominal, unit[, free]) tuples");
    Parameter param;
    param.name = t[0].cast<std::string>();
    param.nominal = t[1].cast<double>();
    param.unit = unit_of(owner, "parameter " + param.name, t[2].cast<std::string>());
    param.free = t.size() == 4 && t[3].cast<bool>();
    parameters_.push_back(param);
  }
  if (actuators_.empty()) throw py::value_error(owner + ": actuators: expected at least one");
  const int n = static_cast<int>(actuators_.size());
  const auto home = as_vector(impl_.attr("home_actuators"), (owner + " home_actuators").c_str(), n);
  home_actuators_ = Eigen::Map<const VectorXd>(home.data(), n);
  VectorXd nominal(parameters_.size());
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    nominal[static_cast<int>(i)] = parameters_[i].nominal;
  const Evaluation at_home = evaluate(nominal, home_actuators_, false);
  rethrow();
  if (!at_home.ok) throw py::value_error(owner + ": forward at the home actuators is not finite");
  home_ = at_home.pose;
}

PythonMechanism::~PythonMechanism() {
  py::gil_scoped_acquire acquire;
  impl_ = py::object();
}

PythonMechanism::Evaluation PythonMechanism::evaluate(const ParamsRef& params,
                                                      const ActuatorsRef& q, bool jacobians) const {
  py::gil_scoped_acquire acquire;
  Evaluation e;
  try {
    const py::object out =
        impl_.attr("forward")(to_numpy(VectorXd(params)), to_numpy(VectorXd(q)), jacobians);
    const auto t = out.cast<py::tuple>();
    if (t.size() != 4)
      throw py::value_error(type_ +
                            ".forward: expected (position, rotation, J_params, J_actuators)");
    const auto position = as_vector(t[0], (type_ + ".forward position").c_str(), 3);
    const auto rotation = as_rows(t[1], (type_ + ".forward rotation").c_str(), 3);
    if (rotation.shape(0) != 3)
      throw py::value_error(type_ + ".forward rotation: expected shape (3, 3)");
    e.pose.translation = Eigen::Map<const Vector3d>(position.data());
    e.pose.rotation = rows_view(rotation);
    if (jacobians) {
      e.J_params = six_rows(t[2], type_ + ".forward J_params", num_parameters());
      e.J_actuators = six_rows(t[3], type_ + ".forward J_actuators", num_actuators());
    }
    e.ok = e.pose.translation.allFinite() && e.pose.rotation.allFinite();
  } catch (...) {
    remember(std::current_exception());
    e.ok = false;
  }
  return e;
}

InverseKinematicsResult PythonMechanism::home_actuators(const ParamsRef&,
                                                        Eigen::Ref<VectorXd> q) const {
  q = home_actuators_;
  return {};
}

InverseKinematicsResult PythonMechanism::inverse_kinematics(const ParamsRef&, const Pose&,
                                                            Eigen::Ref<VectorXd> q) const {
  InverseKinematicsResult r;
  r.status = InverseKinematicsStatus::kUnreachable;
  r.reason = "a mechanism written in Python states no inverse kinematics";
  q.setZero();
  return r;
}

ForwardKinematicsResult PythonMechanism::forward_kinematics(const ParamsRef& params,
                                                            const ActuatorsRef& q, const Pose&,
                                                            const ForwardKinematicsOptions&) const {
  ForwardKinematicsResult result;
  if (!q.allFinite()) {
    result.status = ForwardKinematicsStatus::kInvalidActuators;
    return result;
  }
  const Evaluation e = evaluate(params, q, false);
  if (!e.ok) {
    result.status = ForwardKinematicsStatus::kNonFinite;
    return result;
  }
  result.pose = e.pose;
  return result;
}

void PythonMechanism::pose_jacobian_params(const ParamsRef& params, const ActuatorsRef& q,
                                           const Pose&, Eigen::Ref<Matrix6Xd> J) const {
  const Evaluation e = evaluate(params, q, true);
  if (e.ok)
    J = e.J_params;
  else
    J.setConstant(std::numeric_limits<double>::quiet_NaN());
}

bool PythonMechanism::pose_jacobian_actuators(const ParamsRef& params, const ActuatorsRef& q,
                                              const Pose&, const ForwardKinematicsOptions&,
                                              Eigen::Ref<Matrix6Xd> J) const {
  const Evaluation e = evaluate(params, q, true);
  if (!e.ok) return false;
  J = e.J_actuators;
  return true;
}

void PythonMechanism::remember(std::exception_ptr e) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!error_) error_ = e;
}

void PythonMechanism::rethrow() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
}

namespace {

// kincal's checks of the mechanism's J_pose_params and J_pose_actuators (4 configurations
// each, central differences), as `kincal check` runs them: (name, passed, worst, tolerance,
// detail) per check.
std::vector<py::tuple> check_mechanism(const ModelHandle& h) {
  std::vector<ConformanceCheck> checks;
  {
    py::gil_scoped_release release;
    checks =
        check_mechanism_jacobians([&] { return std::make_shared<MeasurementModel>(*h.model); });
    rethrow_python_errors(*h.model);
  }
  std::vector<py::tuple> out;
  for (const auto& c : checks)
    out.push_back(py::make_tuple(c.name, c.passed, c.worst, c.tolerance, c.detail));
  return out;
}

}  // namespace

void bind_mechanisms(py::module_& m) {
  m.def("_check_mechanism", &check_mechanism, py::arg("model"),
        "kincal's finite-difference checks of the model's mechanism Jacobians (those of "
        "`kincal check`): (name, passed, worst, tolerance, detail) per check.");
}

}  // namespace kincal::python
