// _kincal: the compiled half of the kincal Python package (python/kincal/ is the other).
// Every C++ exception becomes a Python one (pybind11's translation: std::invalid_argument
// and domain_error are ValueError, other std::exception RuntimeError); nothing here aborts.

#include "bindings.hpp"
#include "kincal/framework/io/output_files.hpp"
#include "kincal/version.hpp"

PYBIND11_MODULE(_kincal, m) {
  m.doc() = "kincal's compiled core; use the kincal package, not this module.";
  namespace kp = kincal::python;
  // The output checks' error (one line naming what and where) is a ValueError.
  pybind11::register_exception<kincal::OutputError>(m, "OutputError", PyExc_ValueError);
  kp::bind_interrupt(m);
  kp::bind_models(m);
  kp::bind_measurements(m);
  kp::bind_least_squares(m);
  kp::bind_sensors(m);
  kp::bind_mechanisms(m);
  kp::bind_studies(m);
  kp::bind_workflows(m);
  kp::bind_compensate(m);
  kp::bind_kinematics(m);
  kp::bind_project(m);
  kp::bind_vision(m);
  m.attr("__version__") = KINCAL_VERSION_STRING;
}
