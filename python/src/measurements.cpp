// Measurement files (kincal's CSV) to and from arrays: actuators (n, num_actuators) and
// readings (n, num_readings) with NaN for a reading not taken.

#include <pybind11/stl.h>

#include <fstream>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "kincal/framework/calibration/calibration_problem.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "model_handle.hpp"

namespace kincal::python {

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
        if (a.shape(0) != r.shape(0))
          throw py::value_error("readings: expected " + std::to_string(a.shape(0)) +
                                " rows, one per row of actuators, got " +
                                std::to_string(r.shape(0)));
        Measurements data;
        data.actuators = rows_view(a);
        data.readings = rows_view(r);
        return measurements_to_csv(data, names, h.model->reading_names(), comment);
      },
      py::arg("actuators"), py::arg("readings"), py::arg("model"), py::arg("comment") = "",
      "The CSV text of a measurement file (full precision: it reads back to the same "
      "doubles); each line of `comment` becomes a leading '# ' line.");
  m.def(
      "calibration_residuals",
      [](const ModelHandle& h, const py::object& actuators, const py::object& readings,
         const py::object& values) {
        const int na = h.model->mechanism().num_actuators();
        const auto a = as_rows(actuators, "actuators", na);
        const auto r = as_rows(readings, "readings", h.model->num_readings());
        if (a.shape(0) != r.shape(0))
          throw py::value_error("readings: expected " + std::to_string(a.shape(0)) +
                                " rows, one per row of actuators, got " +
                                std::to_string(r.shape(0)));
        Measurements data;
        data.actuators = rows_view(a);
        data.readings = rows_view(r);
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
        return py::make_tuple(to_numpy(residuals), to_numpy(jacobian), names);
      },
      py::arg("model"), py::arg("actuators"), py::arg("readings"), py::arg("values") = py::none(),
      "The calibration problem's residuals (predicted - measured, weighted by the model's "
      "reading_std; 0 for a missing reading) and their Jacobian with respect to the free "
      "parameters, at the nominal values or `values` (one per parameter): (residuals "
      "(n * num_readings,), jacobian (n * num_readings, num_free), free parameter names).");
}

}  // namespace kincal::python
