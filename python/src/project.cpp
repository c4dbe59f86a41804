// Project files for Python (kincal.run_project, python/kincal/project.py): the library's reader
// (framework/io/project_file.hpp), the record a JSON report keeps of the step it was written
// by, the model file a `model` step writes, and `verify` (framework/workflows/verify.hpp).

#include <optional>

#include "bindings.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/io/project_file.hpp"
#include "kincal/framework/workflows/verify.hpp"
#include "kincal/models/model_io.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

std::optional<nlohmann::ordered_json>& active_record() {
  static std::optional<nlohmann::ordered_json> record;
  return record;
}

py::dict project_dict(const Project& project) {
  py::list steps;
  for (const ProjectStep& step : project.steps) {
    py::list options;
    for (const ProjectOption& option : step.options)
      options.append(py::make_tuple(option.key, option.values, option.is_switch, option.line));
    py::dict entry;
    entry["command"] = step.command;
    entry["line"] = step.line;
    entry["options"] = options;
    steps.append(entry);
  }
  py::dict answer;
  answer["file"] = project.file;
  answer["folder"] = project.folder;
  answer["sha256"] = project.sha256;
  answer["name"] = project.name;
  answer["variables"] = project.variables;
  answer["steps"] = steps;
  // What each step's reports record (project_record), as JSON text per step.
  py::list records;
  for (std::size_t i = 0; i < project.steps.size(); ++i)
    records.append(project_record(project, i).dump());
  answer["records"] = records;
  return answer;
}

}  // namespace

std::string report_json_text(nlohmann::ordered_json report) {
  if (active_record() && report.is_object()) report["project"] = *active_record();
  return report.dump(2) + "\n";
}

void bind_project(py::module_& m) {
  using Overrides = std::vector<std::pair<std::string, std::string>>;
  m.def(
      "_read_project",
      [](const std::string& path, const Overrides& overrides) {
        return project_dict(read_project(path, overrides));
      },
      py::arg("path"), py::arg("overrides"));
  m.def(
      "_project_from_report",
      [](const std::string& report, const Overrides& overrides) {
        JsonLimits limits;
        limits.max_bytes = std::size_t{2} << 30;
        return project_dict(project_from_report(read_json_file(report, "report (JSON)", limits),
                                                report, overrides));
      },
      py::arg("report"), py::arg("overrides"));
  m.def(
      "_set_project_record",
      [](const std::string& record) {
        if (record.empty())
          active_record().reset();
        else
          active_record() = nlohmann::ordered_json::parse(record);
      },
      py::arg("record"));
  m.def(
      "_write_model_file",
      [](const ModelHandle& handle, const std::string& out,
         const std::vector<std::string>& inputs) {
        const OutputPlan plan = plan_outputs(inputs, {{"out", out}});
        write_outputs(
            plan,
            {{"out",
              model_to_json(*handle.model, handle.model->parameters().nominal_values()).dump(2) +
                  "\n"}});
      },
      py::arg("model"), py::arg("out"), py::arg("inputs"));
  m.def(
      "_verify",
      [](const std::string& report, const std::string& model, const std::string& json) {
        std::vector<std::string> inputs = {report};
        if (!model.empty()) inputs.push_back(model);
        const OutputPlan plan = plan_outputs(inputs, {{"json", json}});
        const VerifyResult result = verify_calibration(report, model);
        if (!json.empty()) write_outputs(plan, {{"json", report_json_text(verify_json(result))}});
        py::dict answer;
        answer["model"] = result.model_file;
        answer["match"] = result.match;
        answer["sha256"] = result.sha256;
        answer["expected_sha256"] = result.expected_sha256;
        answer["message"] = result.match ? std::string() : verify_mismatch_text(result);
        return answer;
      },
      py::arg("report"), py::arg("model"), py::arg("json"));
}

}  // namespace kincal::python
