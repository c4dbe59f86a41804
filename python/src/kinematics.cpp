// kincal.fk and kincal.ik: forward and inverse kinematics of one configuration or pose, or of a
// table (framework/workflows/kinematics_table.hpp), as `kincal fk` and `kincal ik` run them
// and with the files they write.

#include "bindings.hpp"
#include "kincal/framework/workflows/kinematics_table.hpp"
#include "model_handle.hpp"

namespace kincal::python {

namespace {

// The table of `request` (data_file set), with its outputs: --out's CSV and --json's document.
py::dict table_answer(const MeasurementModel& model, const std::string& command,
                      const std::string& model_name, const KinematicsTableRequest& request,
                      const std::string& out, const std::string& json,
                      const std::vector<std::string>& inputs) {
  const OutputPlan plan = plan_outputs(inputs, {{"out", out}, {"json", json}});
  KinematicsTable table;
  {
    py::gil_scoped_release release;
    table = kinematics_table(model, request);
  }
  const nlohmann::ordered_json document =
      rows_json("kincal-" + command, model_name, request.data_file, model, table.rows);
  const std::string csv = rows_csv(model, table.rows);
  std::vector<std::pair<std::string, std::string>> contents;
  if (!out.empty()) contents.emplace_back("out", csv);
  if (!json.empty()) contents.emplace_back("json", document.dump(2) + "\n");
  write_outputs(plan, contents);
  py::dict answer;
  answer["report"] = document.dump();
  answer["text"] = csv;
  answer["notes"] = table.notes;
  return answer;
}

// One result's document, written to `json` when given, and its text.
py::dict one_answer(const nlohmann::ordered_json& document, const std::string& text,
                    const std::string& json, const OutputPlan& plan) {
  if (!json.empty()) write_outputs(plan, {{"json", document.dump(2) + "\n"}});
  py::dict answer;
  answer["report"] = document.dump();
  answer["text"] = text;
  return answer;
}

py::dict fk_workflow(const ModelHandle& handle, const std::string& model_name,
                     const std::string& actuators, const std::string& data, const std::string& out,
                     const std::string& json, const std::vector<std::string>& inputs) {
  const MeasurementModel& model = *handle.model;
  const std::string& name = model_name.empty() ? handle.source : model_name;
  if (!data.empty()) {
    if (!actuators.empty()) throw std::invalid_argument("give actuators or data, not both");
    KinematicsTableRequest request;
    request.data_file = data;
    request.option_prefix = "";  // Python's spelling in the notes
    return table_answer(model, "fk", name, request, out, json, inputs);
  }
  if (!out.empty()) throw std::invalid_argument("out writes the table of data; give data");
  if (actuators.empty()) throw std::invalid_argument("actuators (or data) is required");
  const OutputPlan plan = plan_outputs(inputs, {{"json", json}});  // before any work
  const KinematicsRow row = forward_at(model, actuators, "actuators");
  return one_answer(kinematics_row_document(false, name, model, row), forward_row_text(model, row),
                    json, plan);
}

py::dict ik_workflow(const ModelHandle& handle, const std::string& model_name,
                     const std::string& pose, const std::string& data,
                     const std::vector<double>& near, bool seeds, bool all, const std::string& out,
                     const std::string& json, const std::vector<std::string>& inputs) {
  const MeasurementModel& model = *handle.model;
  const std::string& name = model_name.empty() ? handle.source : model_name;
  const int n = model.mechanism().num_actuators();
  if (!near.empty() && static_cast<int>(near.size()) != n)
    throw std::invalid_argument("near: " + std::to_string(near.size()) + " numbers, expected " +
                                std::to_string(n) + " (one value per actuator, in its unit)");
  const VectorXd start =
      Eigen::Map<const VectorXd>(near.data(), static_cast<Eigen::Index>(near.size()));
  if (!data.empty()) {
    if (!pose.empty()) throw std::invalid_argument("give pose or data, not both");
    if (all) throw std::invalid_argument("all takes one pose, not a table (data)");
    KinematicsTableRequest request;
    request.inverse = true;
    request.data_file = data;
    request.seeds = seeds;
    request.near = start;
    request.option_prefix = "";  // Python's spelling in the notes: seeds
    return table_answer(model, "ik", name, request, out, json, inputs);
  }
  if (!out.empty()) throw std::invalid_argument("out writes the table of data; give data");
  if (seeds) throw std::invalid_argument("seeds reads a start per row of data");
  if (pose.empty()) throw std::invalid_argument("pose (or data) is required");
  const OutputPlan plan = plan_outputs(inputs, {{"json", json}});  // before any work
  const VectorXd* from = near.empty() ? nullptr : &start;
  if (all) {
    std::vector<KinematicsRow> solutions;
    {
      py::gil_scoped_release release;
      solutions = inverse_solutions_at(model, pose, "pose", from);
    }
    return one_answer(kinematics_solutions_document(name, model, solutions),
                      inverse_solutions_text(model, solutions, from != nullptr), json, plan);
  }
  const KinematicsRow row = inverse_at(model, pose, "pose", from);
  return one_answer(kinematics_row_document(true, name, model, row),
                    inverse_row_text(model, row) + actuator_units_line(model), json, plan);
}

}  // namespace

void bind_kinematics(py::module_& m) {
  m.def("_fk", &fk_workflow, py::arg("model"), py::arg("model_name"), py::arg("actuators"),
        py::arg("data"), py::arg("out"), py::arg("json"), py::arg("inputs"),
        "Forward kinematics (kincal.fk is its face): a dict with the document's JSON text, "
        "the text (the CSV for a table) and, for a table, the notes.");
  m.def("_ik", &ik_workflow, py::arg("model"), py::arg("model_name"), py::arg("pose"),
        py::arg("data"), py::arg("near"), py::arg("seeds"), py::arg("all"), py::arg("out"),
        py::arg("json"), py::arg("inputs"), "Inverse kinematics (kincal.ik is its face): as _fk.");
}

}  // namespace kincal::python
