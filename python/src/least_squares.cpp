// The generic least-squares layer from Python: a problem whose residuals and Jacobian are
// Python callables, solved by any registered backend. The slow path (docs/python.md): every
// evaluation takes the GIL and calls into Python.

#include <pybind11/stl.h>

#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"

namespace kincal::python {

namespace {

// The problem as Python sees it (kincal.LeastSquaresProblem): the callables and sizes. It
// holds nothing a solve changes, so it can be solved again after a callable raised: each
// solve evaluates it through a CallableSolve of its own.
class CallableProblem {
 public:
  CallableProblem(py::object residuals, py::object jacobian, int num_parameters, int num_residuals,
                  std::vector<std::string> names)
      : residuals_(std::move(residuals)),
        jacobian_(std::move(jacobian)),
        n_(num_parameters),
        m_(num_residuals),
        names_(std::move(names)) {
    if (n_ < 1) throw py::value_error("num_parameters: expected at least 1");
    if (m_ < 1) throw py::value_error("num_residuals: expected at least 1");
    if (!names_.empty() && static_cast<int>(names_.size()) != n_)
      throw py::value_error("parameter_names: expected " + std::to_string(n_) + " names, got " +
                            std::to_string(names_.size()));
  }

  int num_parameters() const { return n_; }
  int num_residuals() const { return m_; }
  std::vector<std::string> parameter_names() const {
    if (!names_.empty()) return names_;
    std::vector<std::string> names;
    for (int i = 0; i < n_; ++i) names.push_back("x" + std::to_string(i));
    return names;
  }
  const py::object& residuals() const { return residuals_; }
  const py::object& jacobian() const { return jacobian_; }

 private:
  py::object residuals_, jacobian_;
  int n_, m_;
  std::vector<std::string> names_;
};

// "[i, j] is nan" (or "[i] is inf" for a vector) for the first entry of `m` that is not finite.
std::string first_non_finite(const Eigen::Ref<const MatrixXd>& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      if (!std::isfinite(m(i, j)))
        return "[" + std::to_string(i) + (m.cols() > 1 ? ", " + std::to_string(j) : "") + "] is " +
               (std::isnan(m(i, j)) ? "nan"
                : m(i, j) > 0       ? "inf"
                                    : "-inf");
  return "";
}

// One solve of a CallableProblem: the LeastSquaresProblem the backend sees, and the first
// exception a callable raised during this solve (the solve stops at it; solve() raises it).
// Residuals or a Jacobian that are not finite are a failed evaluation, as the calibration
// problem's are, with the entry named: a backend then never sees them.
class CallableSolve : public LeastSquaresProblem {
 public:
  explicit CallableSolve(const CallableProblem& problem) : problem_(problem) {}

  int num_parameters() const override { return problem_.num_parameters(); }
  int num_residual_blocks() const override { return 1; }
  int residuals_per_block() const override { return problem_.num_residuals(); }
  std::vector<std::string> parameter_names() const override { return problem_.parameter_names(); }

  bool evaluate_block(int, const VectorXd& x, Eigen::Ref<VectorXd> residuals,
                      Eigen::Ref<MatrixXd>* jacobian, std::string* why) const override {
    const int n = problem_.num_parameters(), m = problem_.num_residuals();
    py::gil_scoped_acquire acquire;
    if (failed()) return fail(why, "an earlier call raised");
    try {
      const py::array_t<double> xs = to_numpy(x);
      const auto r = as_vector(problem_.residuals()(xs), "residuals(x)", m);
      residuals = Eigen::Map<const VectorXd>(r.data(), m);
      if (jacobian) {
        const auto j = as_rows(problem_.jacobian()(xs), "jacobian(x)", n);
        if (j.shape(0) != m)
          throw py::value_error("jacobian(x): expected shape (" + std::to_string(m) + ", " +
                                std::to_string(n) + "), got (" + std::to_string(j.shape(0)) + ", " +
                                std::to_string(n) + ")");
        *jacobian = rows_view(j);
      }
    } catch (py::error_already_set&) {
      remember(std::current_exception());
      return fail(why, "the Python callable raised");
    } catch (const std::exception&) {
      remember(std::current_exception());
      return fail(why, "the Python callable returned a wrong value");
    }
    if (!residuals.allFinite())
      return fail(why, "residuals(x)" + first_non_finite(residuals) + ", expected finite numbers");
    if (jacobian && !jacobian->allFinite())
      return fail(why, "jacobian(x)" + first_non_finite(*jacobian) + ", expected finite numbers");
    return true;
  }

  bool failed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return static_cast<bool>(error_);
  }
  /// Raises the callable's exception, once (pybind11 restores a Python error only once).
  void rethrow() {
    std::exception_ptr error;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      std::swap(error, error_);
    }
    if (error) std::rethrow_exception(error);
  }

 private:
  static bool fail(std::string* why, const std::string& text) {
    if (why) *why = text;
    return false;
  }
  void remember(std::exception_ptr e) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = e;
  }

  const CallableProblem& problem_;
  mutable std::mutex mutex_;
  mutable std::exception_ptr error_;
};

py::dict summary_dict(const Summary& s, const VectorXd& x, bool interrupted) {
  MatrixXd trace(s.trace.size(), 6);
  for (std::size_t i = 0; i < s.trace.size(); ++i) {
    const IterationRecord& r = s.trace[i];
    trace.row(i) << r.iteration, r.cost, r.gradient_norm, r.step_norm, r.damping, r.seconds;
  }
  py::dict d;
  d["x"] = to_numpy(x);
  d["solver"] = s.solver;
  d["termination"] = std::string(to_string(s.termination));
  d["message"] = s.message;
  d["converged"] = s.converged();
  d["iterations"] = s.iterations;
  d["initial_cost"] = s.initial_cost;
  d["final_cost"] = s.final_cost;
  d["residual_evaluations"] = s.residual_evaluations;
  d["jacobian_evaluations"] = s.jacobian_evaluations;
  d["wall_seconds"] = s.wall_seconds;
  d["trace"] = to_numpy(trace);
  d["interrupted"] = interrupted;
  return d;
}

py::dict solve(const CallableProblem& callables, const py::object& x0,
               const std::string& solver_name, int max_iterations, double function_tolerance,
               double parameter_tolerance, double gradient_tolerance, const py::object& lower,
               const py::object& upper, const std::map<std::string, std::string>& backend_options,
               const std::string& loss, int verbosity, bool catch_sigint) {
  CallableSolve problem(callables);
  const int n = problem.num_parameters();
  const auto start = as_vector(x0, "x0", n);
  VectorXd x = Eigen::Map<const VectorXd>(start.data(), n);
  SolverOptions options;
  options.max_iterations = max_iterations;
  options.function_tolerance = function_tolerance;
  options.parameter_tolerance = parameter_tolerance;
  options.gradient_tolerance = gradient_tolerance;
  options.verbosity = verbosity;
  // The settings are parsed once, here, with the solver they are for.
  const std::unique_ptr<Solver> solver = SolverRegistry::global().create(solver_name);
  options.backend = solver->parse_settings(backend_options);
  options.loss = RobustLoss::parse(loss);
  if (lower.is_none() != upper.is_none())
    throw py::value_error("lower, upper: give both bounds or neither");
  if (!lower.is_none()) {
    const auto lo = as_vector(lower, "lower", n), hi = as_vector(upper, "upper", n);
    options.lower_bounds = Eigen::Map<const VectorXd>(lo.data(), n);
    options.upper_bounds = Eigen::Map<const VectorXd>(hi.data(), n);
  }
  solver->check_options(options);
  Summary summary;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    options.callback = [&](const IterationRecord&, const VectorXd&) {
      return sigint_received() || problem.failed() ? CallbackAction::kStop
                                                   : CallbackAction::kContinue;
    };
    summary = solver->solve(problem, x, options);
    interrupted = sigint.interrupted();
  }
  problem.rethrow();
  return summary_dict(summary, x, interrupted);
}

}  // namespace

void bind_least_squares(py::module_& m) {
  py::register_exception<InvalidSolverOptions>(m, "InvalidSolverOptions", PyExc_ValueError);
  py::class_<CallableProblem>(m, "LeastSquaresProblem", R"doc(min_x 1/2 |r(x)|^2 with r and its
Jacobian given as Python callables: residuals(x) -> (num_residuals,), jacobian(x) ->
(num_residuals, num_parameters). The slow path: each evaluation calls into Python with the GIL
held. A callable that raises stops the solve and the exception propagates from solve().)doc")
      .def(py::init<py::object, py::object, int, int, std::vector<std::string>>(),
           py::arg("residuals"), py::arg("jacobian"), py::arg("num_parameters"),
           py::arg("num_residuals"), py::arg("parameter_names") = std::vector<std::string>{},
           "The problem of residuals(x) and jacobian(x) over num_parameters unknowns (named "
           "parameter_names, default x0, x1, ...) and num_residuals residuals.")
      .def_property_readonly("num_parameters", &CallableProblem::num_parameters,
                             "Number of unknowns.")
      .def_property_readonly("num_residuals", &CallableProblem::num_residuals,
                             "Number of residuals.")
      .def_property_readonly("parameter_names", &CallableProblem::parameter_names,
                             "The unknowns' names, for reports.");
  m.def("_solve", &solve, py::arg("problem"), py::arg("x0"), py::arg("solver"),
        py::arg("max_iterations"), py::arg("function_tolerance"), py::arg("parameter_tolerance"),
        py::arg("gradient_tolerance"), py::arg("lower"), py::arg("upper"),
        py::arg("backend_options"), py::arg("loss"), py::arg("verbosity"), py::arg("catch_sigint"),
        "Solves `problem` from x0 with a registered backend (kincal.solve wraps this).");
  m.def(
      "solvers",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& info : SolverRegistry::global().list())
          out.emplace_back(info.name, info.description);
        return out;
      },
      "The registered solvers as (name, description) pairs; a family is named as "
      "nlopt:<ALGORITHM>.");
}

}  // namespace kincal::python
