// kincal.Model: a measurement model (mechanism, sensors, parameters with names, units,
// nominal values and the free mask), from a preset or a model file, and its forward and
// inverse kinematics over arrays of configurations (the code of `kincal fk` and `kincal ik`).

#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "kincal/framework/extension/plugin.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/workflows/kinematics_rows.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/presets.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

py::array_t<bool> to_numpy_bool(const std::vector<bool>& v) {
  py::array_t<bool> out(static_cast<py::ssize_t>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) out.mutable_data()[i] = v[i];
  return out;
}

// The values of every parameter in model order, one field at a time.
template <class F>
VectorXd parameter_field(const MeasurementModel& model, F field) {
  const auto& all = model.parameters().all();
  VectorXd v(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) v[i] = field(all[i]);
  return v;
}

// Rows of a kinematics table as arrays; a failed row is NaN with its status and reason.
py::tuple rows_to_arrays(const MeasurementModel& model, const std::vector<KinematicsRow>& rows) {
  const int n = static_cast<int>(rows.size());
  MatrixXd actuators = MatrixXd::Constant(n, model.mechanism().num_actuators(), kNaN);
  MatrixXd poses = MatrixXd::Constant(n, 6, kNaN);
  MatrixXd readings = MatrixXd::Constant(n, model.num_readings(), kNaN);
  std::vector<std::string> status(n), reason(n);
  for (int i = 0; i < n; ++i) {
    const KinematicsRow& r = rows[i];
    if (r.actuators_known) actuators.row(i) = r.actuators.transpose();
    if (r.pose_known)
      for (int k = 0; k < 6; ++k) poses(i, k) = r.pose[k];
    if (r.ok()) readings.row(i) = r.readings.transpose();
    status[i] = r.status;
    reason[i] = r.reason;
  }
  return py::make_tuple(to_numpy(actuators), to_numpy(poses), to_numpy(readings), status, reason);
}

}  // namespace

void bind_models(py::module_& m) {
  py::class_<ModelHandle>(m, "Model", R"doc(A measurement model: a mechanism, its sensors and
one parameter vector with names, units, nominal values and a free mask (model files:
docs/calibrating-a-machine.md). Use kincal.Model.preset(), kincal.Model.load() or
kincal.Model.from_json().)doc")
      .def_static(
          "preset",
          [](const std::string& name) {
            return ModelHandle{make_preset(name), name};
          },
          py::arg("name"), "The built-in model `name` (kincal.presets() lists them).")
      .def_static(
          "load",
          [](const std::string& path) {
            // Without the GIL: the file may be a FIFO another Python thread writes.
            py::gil_scoped_release release;
            return ModelHandle{load_model(path), path};
          },
          py::arg("path"), "Reads a model file (JSON). Errors name the file and the field.")
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& source) {
            // Read as a model file is: size and nesting limits, a key given twice refused.
            return ModelHandle{model_from_text(text, source), source};
          },
          py::arg("text"), py::arg("source") = "<string>",
          "A model from the text of a model file, read as Model.load reads the file (at most "
          "16 MiB and 64 levels of nesting, no key given twice, finite numbers); `source` "
          "names it in messages. ValueError for anything a model file may not hold.")
      .def(
          "to_json",
          [](const ModelHandle& h, const py::object& values) {
            VectorXd v = h.model->parameters().nominal_values();
            if (!values.is_none()) {
              const auto a = as_vector(values, "values", h.model->num_parameters());
              v = Eigen::Map<const VectorXd>(a.data(), a.shape(0));
            }
            return model_to_json(*h.model, v).dump(2) + "\n";
          },
          py::arg("values") = py::none(),
          "The model file's text, with the nominal values or `values` (one per parameter).")
      .def(
          "copy", [](const ModelHandle& h) { return h.copy(); }, "An independent copy.")
      // Pickled as its model file's text (to a Dask worker, say); a model no file can hold
      // (Python sensors) raises ValueError. A pickle is text from elsewhere: it is read back
      // as a model file is, with the same limits and checks.
      .def(py::pickle(
          [](const ModelHandle& h) {
            return py::make_tuple(
                model_to_json(*h.model, h.model->parameters().nominal_values()).dump(), h.source);
          },
          [](const py::tuple& t) {
            if (t.size() != 2 || !py::isinstance<py::str>(t[0]) || !py::isinstance<py::str>(t[1]))
              throw py::value_error(
                  "kincal.Model pickle: expected (model file text, source), two strings");
            const auto source = t[1].cast<std::string>();
            return ModelHandle{model_from_text(t[0].cast<std::string>(), "kincal.Model pickle"),
                               source};
          }))
      .def(
          "with_values",
          [](const ModelHandle& h, const py::object& values) {
            const auto a = as_vector(values, "values", h.model->num_parameters());
            return ModelHandle{
                model_with_values(*h.model, Eigen::Map<const VectorXd>(a.data(), a.shape(0))),
                h.source};
          },
          py::arg("values"), "A copy whose nominal values are `values` (same free mask).")
      .def_readonly("source", &ModelHandle::source, "The preset's name or the file it came from.")
      .def_property_readonly(
          "parameter_names", [](const ModelHandle& h) { return h.model->parameters().names(); },
          "Every parameter's name, in model order.")
      .def_property_readonly(
          "parameter_units",
          [](const ModelHandle& h) {
            std::vector<std::string> u;
            for (const auto& p : h.model->parameters().all()) u.push_back(p.unit);
            return u;
          },
          "Every parameter's unit, 'mm' or 'rad'.")
      .def_property_readonly(
          "nominal",
          [](const ModelHandle& h) { return to_numpy(h.model->parameters().nominal_values()); },
          "Nominal values (a new float64 array, model order).")
      .def_property_readonly(
          "free",
          [](const ModelHandle& h) {
            std::vector<bool> f;
            for (const auto& p : h.model->parameters().all()) f.push_back(p.free);
            return to_numpy_bool(f);
          },
          "The free mask (a new bool array): True for an estimated parameter.")
      .def_property_readonly(
          "prior_std",
          [](const ModelHandle& h) {
            return to_numpy(
                parameter_field(*h.model, [](const Parameter& p) { return p.prior_std; }));
          },
          "Per-parameter prior standard deviation (0: none).")
      .def(
          "set_free",
          [](ModelHandle& h, const std::string& pattern, bool free) {
            return h.model->parameters().set_free(pattern, free);
          },
          py::arg("pattern"), py::arg("free") = true,
          "Frees (or fixes) the parameters whose names match the glob `pattern`; returns how "
          "many. A pattern that matches nothing raises ValueError.")
      .def_property_readonly(
          "actuator_names",
          [](const ModelHandle& h) { return h.model->mechanism().actuator_names(); },
          "The actuators (measurement file columns), in order.")
      .def_property_readonly(
          "actuator_units",
          [](const ModelHandle& h) {
            std::vector<std::string> u;
            for (const auto& a : h.model->mechanism().actuators()) u.push_back(a.unit);
            return u;
          },
          "Each actuator's unit.")
      .def_property_readonly(
          "reading_names", [](const ModelHandle& h) { return h.model->reading_names(); },
          "The sensors' readings (measurement file columns), in order.")
      .def_property_readonly(
          "reading_units", [](const ModelHandle& h) { return h.model->reading_units(); },
          "Each reading's unit.")
      .def(
          "forward_kinematics",
          [](const ModelHandle& h, const py::object& actuators) {
            const auto a = as_rows(actuators, "actuators", h.model->mechanism().num_actuators());
            const ConstRowMap q = rows_view(a);
            std::vector<KinematicsRow> rows(q.rows());
            {
              py::gil_scoped_release release;
              for (Eigen::Index i = 0; i < q.rows(); ++i)
                rows[i] = forward_row(*h.model, q.row(i).transpose());
            }
            const py::tuple t = rows_to_arrays(*h.model, rows);
            return py::make_tuple(t[1], t[2], t[3], t[4]);
          },
          py::arg("actuators"),
          "Forward kinematics at the nominal values: actuators (n, num_actuators) -> (poses "
          "(n, 6): x, y, z mm and rx, ry, rz deg (Z-Y-X), readings (n, num_readings), status, "
          "reason), as `kincal fk`. A failed row is NaN with its status and reason.")
      .def(
          "inverse_kinematics",
          [](const ModelHandle& h, const py::object& poses, const py::object& near) {
            const auto a = as_rows(poses, "poses", 6);
            const ConstRowMap p = rows_view(a);
            const Eigen::Index na = h.model->mechanism().num_actuators();
            // near: one configuration for every row, or one per row (a seed each).
            py::array_t<double, py::array::c_style> starts;
            if (!near.is_none()) {
              starts = as_rows(near, "near", na);
              if (starts.shape(0) != 1 && starts.shape(0) != p.rows())
                throw std::invalid_argument("near: expected one configuration, or one per pose (" +
                                            std::to_string(p.rows()) + "), got " +
                                            std::to_string(starts.shape(0)));
            }
            const bool with_starts = !near.is_none();
            const ConstRowMap s = with_starts ? rows_view(starts) : ConstRowMap(nullptr, 0, na);
            std::vector<KinematicsRow> rows(p.rows());
            {
              py::gil_scoped_release release;
              VectorXd start(na);
              for (Eigen::Index i = 0; i < p.rows(); ++i) {
                std::array<double, 6> pose;
                for (int k = 0; k < 6; ++k) pose[k] = p(i, k);
                if (with_starts) start = s.row(s.rows() == 1 ? 0 : i).transpose();
                rows[i] = inverse_row(*h.model, pose, with_starts ? &start : nullptr);
              }
            }
            const py::tuple t = rows_to_arrays(*h.model, rows);
            return py::make_tuple(t[0], t[2], t[3], t[4]);
          },
          py::arg("poses"), py::arg("near") = py::none(),
          "Inverse kinematics at the nominal values: poses (n, 6) as forward_kinematics gives "
          "them -> (actuators (n, num_actuators), readings, status, reason), as `kincal ik`. "
          "`near`: the configuration each solution should be nearest (a serial arm's branch), "
          "one for every pose (`--near`) or one per pose (`--seeds`); default from home.")
      .def("__repr__", [](const ModelHandle& h) {
        return "<kincal.Model " + h.source + ": " + std::to_string(h.model->num_parameters()) +
               " parameters, " + std::to_string(h.model->parameters().num_free()) + " free>";
      });

  m.def(
      "presets",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& p : list_presets()) out.emplace_back(p.name, p.description);
        return out;
      },
      "The built-in models as (name, description) pairs.");
  m.def(
      "load_plugin",
      [](const std::string& path) {
        try {
          load_plugin(path);
        } catch (const PluginError& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("path"),
      "Loads a kincal plug-in (a shared library built with kincal_add_plugin) into the "
      "registries every model and command of this module uses: its mechanisms, sensors, "
      "presets, export formats and solvers become usable by name, as with `kincal --plugin`. "
      "ValueError, with nothing added, for a file that is not a plug-in, one built for another "
      "kincal version or ABI, or a name that clashes with a registered one. Loading the same "
      "file again does nothing.");
  m.def("loaded_plugins", &loaded_plugins,
        "The plug-ins loaded in this process so far (absolute paths, in load order).");
  m.def(
      "_array_address",
      [](const py::object& value, const char* argument, py::ssize_t cols) {
        return reinterpret_cast<std::uintptr_t>(as_rows(value, argument, cols).data());
      },
      "The address of the data kincal reads for `value` (tests of the no-copy path).");
}

}  // namespace kincal::python
