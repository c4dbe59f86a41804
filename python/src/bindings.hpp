#pragma once
// The pieces of the _kincal module (python/src/module.cpp binds them in this order) and the
// array conversions they share. docs/python.md says what each costs in copies.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // in every file: the casters of std::vector must agree (ODR)

#include <nlohmann/json.hpp>
#include <string>

#include "kincal/framework/base/types.hpp"
#include "kincal/framework/io/standard_output.hpp"

namespace kincal::python {

namespace py = pybind11;

void bind_interrupt(py::module_& m);
void bind_models(py::module_& m);
void bind_measurements(py::module_& m);
void bind_least_squares(py::module_& m);
void bind_sensors(py::module_& m);
void bind_mechanisms(py::module_& m);
void bind_studies(py::module_& m);
void bind_workflows(py::module_& m);
void bind_vision(py::module_& m);

/// The module's standard output as the output writers take it
/// (framework/io/standard_output.hpp): a stream of its own that nothing reads, since the
/// module prints nothing and passes "-" as the file "./-".
const StandardOutput& python_output();
void bind_compensate(py::module_& m);
void bind_kinematics(py::module_& m);
void bind_project(py::module_& m);

/// `report` as a JSON report's text, with the key "project" (the step's record) while
/// kincal.run_project runs a step (python/src/project.cpp).
std::string report_json_text(nlohmann::ordered_json report);

}  // namespace kincal::python

#include "kincal/framework/io/output_plan.hpp"

namespace kincal::python {

/// The outputs asked for, checked before any work against the files read (`inputs`) and each
/// other (python/src/workflows.cpp).
OutputPlan plan_outputs(const std::vector<std::string>& inputs,
                        const std::vector<std::pair<std::string, std::string>>& outputs);
/// Writes (label, content) pairs as the program does (whole or not at all).
void write_outputs(const OutputPlan& plan,
                   const std::vector<std::pair<std::string, std::string>>& contents);

/// Row-major view of a float64 matrix: what numpy gives without a copy.
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstRowMap = Eigen::Map<const RowMatrixXd>;

/// A (rows, `cols`) float64 C-contiguous array holding `value`: `value` itself when it is
/// one already (no copy), else one explicit copy (another dtype that converts exactly to
/// float64, another memory order, a stride). A 1-D array of `cols` values is one row. Throws
/// py::value_error naming `argument` and the expected shape for any other shape, and for a
/// dtype that is not a real number (complex, object, strings, bool).
py::array_t<double, py::array::c_style> as_rows(const py::handle& value, const char* argument,
                                                py::ssize_t cols);
/// The same for a vector of `size` values (size < 0: any size).
py::array_t<double, py::array::c_style> as_vector(const py::handle& value, const char* argument,
                                                  py::ssize_t size);
/// A view of a C-contiguous float64 array returned by as_rows.
inline ConstRowMap rows_view(const py::array_t<double, py::array::c_style>& a) {
  return ConstRowMap(a.data(), a.shape(0), a.shape(1));
}

/// A numpy array that owns a copy of `m` (Eigen is column-major; numpy gets C order).
py::array_t<double> to_numpy(const MatrixXd& m);
py::array_t<double> to_numpy(const VectorXd& v);

}  // namespace kincal::python
