// Measurement files (kincal's CSV) to and from arrays: actuators (n, num_actuators) and
// readings (n, num_readings) with NaN for a reading not taken.

#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/framework/io/output_files.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

// Actuators and readings (as_rows' arrays) with as many rows.
Measurements measurements_of(const py::array_t<double, py::array::c_style>& actuators,
                             const py::array_t<double, py::array::c_style>& readings) {
  if (actuators.shape(0) != readings.shape(0))
    throw py::value_error("readings: expected " + std::to_string(actuators.shape(0)) +
                          " rows, one per row of actuators, got " +
                          std::to_string(readings.shape(0)));
  Measurements data;
  data.actuators = rows_view(actuators);
  data.readings = rows_view(readings);
  return data;
}

// A residual or derivative that is not finite (a reading of 1e308 weighted by a small
// reading_std overflows) is an error naming the row and the reading, never a value returned.
void check_finite(const VectorXd& residuals, const MatrixXd& jacobian,
                  const std::vector<std::string>& readings,
                  const std::vector<std::string>& parameters) {
  const auto where = [&](Eigen::Index k) {
    const auto per_row = static_cast<Eigen::Index>(readings.size());
    return "row " + std::to_string(k / per_row) + ", reading '" + readings[k % per_row] + "'";
  };
  const auto text = [](double v) { return std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf"; };
  for (Eigen::Index k = 0; k < residuals.size(); ++k)
    if (!std::isfinite(residuals[k]))
      throw py::value_error(where(k) + ": the residual (predicted - measured, weighted) is " +
                            text(residuals[k]) +
                            " at these values; expected readings on the scale of the machine");
  for (Eigen::Index k = 0; k < jacobian.rows(); ++k)
    for (Eigen::Index j = 0; j < jacobian.cols(); ++j)
      if (!std::isfinite(jacobian(k, j)))
        throw py::value_error(where(k) + ": the derivative with respect to '" + parameters[j] +
                              "' is " + text(jacobian(k, j)) + " at these values");
}

}  // namespace

void bind_measurements(py::module_& m) {
  m.def(
      "read_measurements",
      [](const std::string& path, const ModelHandle& h, bool allow_no_readings) {
        MeasurementTable t;
        {
          py::gil_scoped_release release;
          t = allow_no_readings ? read_model_columns(path, *h.model)
                                : read_measurements(path, *h.model);
        }
        return py::make_tuple(to_numpy(t.data.actuators), to_numpy(t.data.readings), t.notices);
      },
      py::arg("path"), py::arg("model"), py::arg("allow_no_readings") = false,
      "Reads a measurement file for `model` (the code of `kincal calibrate --data`): returns "
      "(actuators, readings, notices). Unit suffixes on column names are converted. Errors "
      "are ValueError naming the file and line.");
  m.def(
      "measurements_to_csv",
      [](const py::object& actuators, const py::object& readings, const ModelHandle& h,
         const std::string& comment) {
        const auto names = h.model->mechanism().actuator_names();
        const auto a = as_rows(actuators, "actuators", static_cast<py::ssize_t>(names.size()));
        const auto r = as_rows(readings, "readings", h.model->num_readings());
        return measurements_to_csv(measurements_of(a, r), names, h.model->reading_names(), comment);
      },
      py::arg("actuators"), py::arg("readings"), py::arg("model"), py::arg("comment") = "",
      "The CSV text of a measurement file (full precision: it reads back to the same "
      "doubles); each line of `comment` becomes a leading '# ' line. ValueError for values "
      "a measurement file cannot hold (see check_measurements).");
  m.def(
      "check_measurements",
      [](const py::object& actuators, const py::object& readings,
         const std::vector<std::string>& actuator_names,
         const std::vector<std::string>& reading_names) {
        const auto a = as_rows(actuators, "actuators", py::ssize_t(actuator_names.size()));
        const auto r = as_rows(readings, "readings", py::ssize_t(reading_names.size()));
        check_measurements_writable(measurements_of(a, r), actuator_names, reading_names);
      },
      py::arg("actuators"), py::arg("readings"), py::arg("actuator_names"),
      py::arg("reading_names"),
      "ValueError unless these columns could be a measurement file kincal reads back: names "
      "of the name policy (docs/reliability.md, \"Names\"), none twice, one per column, "
      "finite actuator values, readings finite or NaN (not taken).");
  m.def(
      "write_measurements",
      [](const std::string& path, const py::object& actuators, const py::object& readings,
         const std::vector<std::string>& actuator_names,
         const std::vector<std::string>& reading_names, const std::string& comment) {
        const auto a = as_rows(actuators, "actuators", py::ssize_t(actuator_names.size()));
        const auto r = as_rows(readings, "readings", py::ssize_t(reading_names.size()));
        const std::string text =
            measurements_to_csv(measurements_of(a, r), actuator_names, reading_names, comment);
        // As the program writes its files: whole or not at all
        // (framework/io/output_files.hpp). "-" is a file here, not standard output.
        py::gil_scoped_release release;
        write_files_atomically({{path == "-" ? "./-" : path, text}}, python_output());
      },
      py::arg("path"), py::arg("actuators"), py::arg("readings"), py::arg("actuator_names"),
      py::arg("reading_names"), py::arg("comment") = "",
      "Writes a measurement file as the program writes its files (a temporary file renamed "
      "over the target); ValueError, writing nothing, for what check_measurements refuses "
      "or a path kincal does not write (a directory, a read-only file...).");
  m.def(
      "calibration_residuals",
      [](const ModelHandle& h, const py::object& actuators, const py::object& readings,
         const py::object& values) {
        const int na = h.model->mechanism().num_actuators();
        const auto a = as_rows(actuators, "actuators", na);
        const auto r = as_rows(readings, "readings", h.model->num_readings());
        const Measurements data = measurements_of(a, r);
        VectorXd full = h.model->parameters().nominal_values();
        if (!values.is_none()) {
          const auto v = as_vector(values, "values", h.model->num_parameters());
          full = Eigen::Map<const VectorXd>(v.data(), v.shape(0));
        }
        VectorXd residuals;
        MatrixXd jacobian;
        std::string why;
        bool ok = false;
        std::vector<std::string> names;
        {
          py::gil_scoped_release release;
          const CalibrationProblem problem(h.model, data, full,
                                           h.model->parameters().free_indices());
          ok = problem.evaluate(problem.initial_free_parameters(), &residuals, &jacobian, &why);
          names = problem.parameter_names();
        }
        if (!ok) throw py::value_error("the residuals cannot be computed at these values: " + why);
        check_finite(residuals, jacobian, h.model->reading_names(), names);
        return py::make_tuple(to_numpy(residuals), to_numpy(jacobian), names);
      },
      py::arg("model"), py::arg("actuators"), py::arg("readings"), py::arg("values") = py::none(),
      "The calibration problem's residuals (predicted - measured, weighted by the model's "
      "reading_std; 0 for a missing reading) and their Jacobian with respect to the free "
      "parameters, at the nominal values or `values` (one per parameter): (residuals "
      "(n * num_readings,), jacobian (n * num_readings, num_free), free parameter names).");
}

}  // namespace kincal::python
