// kincal.compensate: corrected targets (framework/workflows/compensate.hpp), the library's
// workflow as `kincal compensate` runs it.

#include <optional>

#include "bindings.hpp"
#include "kincal/framework/workflows/compensate.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

py::dict compensate_workflow(const ModelHandle& handle, const std::string& targets,
                             const std::optional<ModelHandle>& nominal,
                             const std::vector<double>& near, const std::optional<double>& payload,
                             double tolerance, const std::string& out, const std::string& json,
                             const std::vector<std::string>& inputs) {
  if (!(tolerance > 0)) throw std::invalid_argument("tolerance: expected a value > 0");
  const OutputPlan plan = plan_outputs(inputs, {{"out", out}, {"json", json}});
  const MeasurementModel& model = *handle.model;
  std::vector<std::pair<std::string, double>> given;
  if (payload) {
    const auto names = model.mechanism().actuator_names();
    if (std::find(names.begin(), names.end(), "payload") == names.end())
      throw std::invalid_argument("payload: the model has no payload column");
    if (!(*payload >= 0)) throw std::invalid_argument("payload: expected a mass >= 0 kg");
    given.emplace_back("payload", *payload);
  }
  CompensateRequest request;
  request.model = handle.model;
  request.tolerance = tolerance;
  CompensateResult result;
  {
    py::gil_scoped_release release;
    request.targets = read_compensate_targets(
        targets, model, nominal ? nominal->model.get() : nullptr,
        Eigen::Map<const VectorXd>(near.data(), static_cast<Eigen::Index>(near.size())), given);
    result = compensate(request);
  }
  const std::string csv = compensated_csv(model, result);
  nlohmann::ordered_json summary = compensate_json(model, result);
  summary["targets"] = targets;
  std::vector<std::pair<std::string, std::string>> contents;
  if (!out.empty()) contents.emplace_back("out", csv);
  if (!json.empty()) contents.emplace_back("json", report_json_text(summary));
  write_outputs(plan, contents);
  MatrixXd commands(static_cast<Eigen::Index>(result.rows.size()),
                    model.mechanism().num_actuators());
  std::vector<std::string> statuses;
  for (std::size_t r = 0; r < result.rows.size(); ++r) {
    const CompensatedRow& row = result.rows[r];
    if (row.ok())
      commands.row(static_cast<Eigen::Index>(r)) = row.commands.transpose();
    else
      commands.row(static_cast<Eigen::Index>(r)).setConstant(NAN);
    statuses.push_back(row.status);
  }
  py::dict answer;
  answer["report"] = summary.dump();
  answer["text"] = compensate_text(model, result);
  answer["commands"] = to_numpy(commands);
  answer["statuses"] = statuses;
  return answer;
}

}  // namespace

void bind_compensate(py::module_& m) {
  m.def("_compensate", &compensate_workflow, py::arg("model"), py::arg("targets"),
        py::arg("nominal"), py::arg("near"), py::arg("payload"), py::arg("tolerance"),
        py::arg("out"), py::arg("json"), py::arg("inputs"),
        "The compensate workflow (kincal.compensate is its face): a dict with the summary's "
        "JSON text, the text, the commands (rows x actuators, NaN where a row failed) and the "
        "rows' statuses.");
}

}  // namespace kincal::python
