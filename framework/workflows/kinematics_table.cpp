#include "kincal/framework/workflows/kinematics_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/calibration/data_checks.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/framework/workflows/option_name.hpp"

namespace kincal {

namespace {

// Whether a note of read_measurements is about one of `names` it did not read.
bool ignores_one_of(const std::string& note, const std::vector<std::string>& names) {
  return std::any_of(names.begin(), names.end(), [&](const std::string& name) {
    return note.find("ignoring column '" + name + "'") != std::string::npos;
  });
}

// "a,b,c" -> its numbers, each field with its unit suffix (one of `suffixes`) split off into
// `units`; throws "<label> '<text>': field N '...' is not a finite number (expected ...)".
std::vector<double> numbers_of(const std::string& text, const std::string& label,
                               const std::string& expected,
                               const std::vector<std::string>& suffixes,
                               std::vector<std::string>* units) {
  std::vector<double> values;
  for (std::string::size_type start = 0;;) {
    const auto comma = text.find(',', start);
    std::string field = text.substr(start, comma - start);
    std::string unit;
    for (const std::string& suffix : suffixes)
      if (field.size() > suffix.size() &&
          field.compare(field.size() - suffix.size(), suffix.size(), suffix) == 0) {
        unit = suffix;
        field.erase(field.size() - suffix.size());
        break;
      }
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0' || !std::isfinite(v))
      throw std::invalid_argument(label + " '" + text + "': field " +
                                  std::to_string(values.size() + 1) + " '" + field +
                                  "' is not a finite number (expected " + expected + ")");
    values.push_back(v);
    if (units) units->push_back(unit);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return values;
}

// The row, or the error its status is: `label` '`text`': why; expected ...
const KinematicsRow& computed(const KinematicsRow& row, const std::string& text,
                              const std::string& label, const std::string& values,
                              const std::string& expected) {
  if (row.status == "overflow")
    throw std::invalid_argument(label + " '" + text + "': the " + values +
                                " at this pose are not finite numbers (the arithmetic "
                                "overflows); expected " +
                                expected);
  if (!row.ok())
    throw std::invalid_argument(label + " '" + text + "': " + row.reason + "; expected " +
                                expected);
  return row;
}

const char* const kPoseExpected = "x,y,z in mm and rx,ry,rz in degrees";

}  // namespace

std::array<double, 6> parse_pose_values(const std::string& text, const std::string& label) {
  const std::vector<double> v = numbers_of(text, label, kPoseExpected, {}, nullptr);
  if (v.size() != 6)
    throw std::invalid_argument(label + " '" + text + "': " + std::to_string(v.size()) +
                                " numbers, expected 6 (" + kPoseExpected + ")");
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

KinematicsRow forward_at(const MeasurementModel& model, const std::string& text,
                         const std::string& label) {
  const std::vector<double> q = parse_actuator_values(text, model, label);
  const KinematicsRow row =
      forward_row(model, Eigen::Map<const VectorXd>(q.data(), static_cast<Eigen::Index>(q.size())));
  if (row.status == "overflow")
    return computed(row, text, label, "readings", "actuator values of the machine's workspace");
  return computed(row, text, label, "", "actuator values the model can reach");
}

KinematicsRow inverse_at(const MeasurementModel& model, const std::string& text,
                         const std::string& label, const VectorXd* near) {
  const KinematicsRow row = inverse_row(model, parse_pose_values(text, label), near);
  if (row.status == "overflow")
    return computed(row, text, label, "actuator values or readings",
                    "a pose near the machine's workspace");
  return computed(row, text, label, "", "a pose the model can reach");
}

std::vector<KinematicsRow> inverse_solutions_at(const MeasurementModel& model,
                                                const std::string& text, const std::string& label,
                                                const VectorXd* near) {
  std::vector<KinematicsRow> solutions =
      inverse_solutions(model, parse_pose_values(text, label), near);
  if (solutions.empty())
    throw std::invalid_argument(label + " '" + text +
                                "': no solution found from 201 starts; expected a pose the model "
                                "can reach");
  return solutions;
}

std::vector<double> parse_actuator_values(const std::string& text, const MeasurementModel& model,
                                          const std::string& label) {
  const auto& actuators = model.mechanism().actuators();
  std::string expected;
  for (const auto& a : actuators)
    expected += (expected.empty() ? "" : ",") + a.name + " (" + a.unit + ")";
  std::vector<std::string> units;
  std::vector<double> q = numbers_of(text, label, expected, {"deg", "rad", "mm", "m"}, &units);
  if (q.size() != actuators.size())
    throw std::invalid_argument(label + " '" + text + "': " + std::to_string(q.size()) +
                                " numbers, expected " + std::to_string(actuators.size()) + " (" +
                                expected + ")");
  for (std::size_t i = 0; i < q.size(); ++i) {
    const std::string& own = actuators[i].unit;
    const std::string& unit = units[i];
    const std::string value = label + " '" + text + "': " + actuators[i].name + " = ";
    if (unit.empty()) {
      if (own == kRadian && std::abs(q[i]) > 2 * M_PI * (1 + 1e-9)) {
        const std::string shown = format_text("%g", q[i]);
        throw std::invalid_argument(
            value + shown +
            " is beyond one turn, which looks like degrees; revolute joints take radians: write " +
            shown + "deg (a unit after each value: deg, rad, mm, m) or give radians");
      }
      continue;
    }
    const double factor = own == kRadian ? (unit == "deg"   ? kRadiansPerDegree
                                            : unit == "rad" ? 1
                                                            : 0)
                                         : (unit == "m"    ? 1000
                                            : unit == "mm" ? 1
                                                           : 0);
    if (factor == 0)
      throw std::invalid_argument(
          value + "a value in " + unit + ", but " + actuators[i].name + " is " +
          (own == kRadian ? "an angle: expected deg or rad" : "a length: expected mm or m"));
    q[i] *= factor;
  }
  return q;
}

KinematicsTable kinematics_table(const MeasurementModel& model,
                                 const KinematicsTableRequest& request) {
  const std::vector<std::string> actuator_names = model.mechanism().actuator_names();
  const auto na = static_cast<Eigen::Index>(actuator_names.size());
  if (!request.inverse && request.seeds)
    throw std::invalid_argument("seeds are a start per row of a table of poses (ik)");
  if (request.seeds && request.near.size() > 0)
    throw std::invalid_argument("give near or seeds, not both");
  if (request.near.size() > 0 && request.near.size() != na)
    throw std::invalid_argument("near: expected " + std::to_string(na) +
                                " actuator values, one per actuator");
  // fk reads actuator columns, ik pose columns (whose names say mm and deg already) and, with
  // seeds, the actuator columns after them: those take unit suffixes.
  std::vector<std::string> columns = request.inverse ? kPoseColumns : actuator_names;
  if (request.seeds) columns.insert(columns.end(), actuator_names.begin(), actuator_names.end());
  MeasurementTable table = read_measurements(request.data_file, columns, {}, request.limits);
  const bool reads_actuators = !request.inverse || request.seeds;
  if (reads_actuators) {
    std::vector<std::string> units(columns.size() - actuator_names.size(), "");
    for (const auto& a : model.mechanism().actuators()) units.push_back(a.unit);
    convert_column_units(table, units, {}, request.data_file);
    if (!request.inverse) {
      const std::string hint = check_data_units(model, model.parameters().nominal_values(), table);
      if (!hint.empty()) throw std::invalid_argument(request.data_file + ": " + hint);
    }
  }

  KinematicsTable result;
  // A measurement file given to fk has reading columns: expected there, not worth a note. The
  // actuator columns of a table of poses (ik) are not "not an actuator": one note says how
  // they would be used.
  bool actuator_columns_ignored = false;
  for (const std::string& n : table.notices) {
    const bool actuator_column = ignores_one_of(n, actuator_names);
    actuator_columns_ignored = actuator_columns_ignored || actuator_column;
    if (!actuator_column && !ignores_one_of(n, model.reading_names())) result.notes.push_back(n);
  }
  if (actuator_columns_ignored)
    result.notes.push_back(request.data_file + ": the actuator columns are not read" +
                           (request.inverse ? " (" + option_name(request.option_prefix, "seeds") +
                                                  " starts each row from them)"
                                            : std::string()));

  const Measurements& data = table.data;
  const VectorXd* near = request.near.size() > 0 ? &request.near : nullptr;
  result.rows.reserve(static_cast<std::size_t>(data.size()));
  for (int r = 0; r < data.size(); ++r) {
    KinematicsRow row;
    if (!request.inverse) {
      row = forward_row(model, data.actuators.row(r).transpose());
    } else {
      const auto v = data.actuators.row(r);
      const std::array<double, 6> pose = {v[0], v[1], v[2], v[3], v[4], v[5]};
      // With seeds, this row's own start: the configuration in its actuator columns.
      const VectorXd seed = request.seeds ? VectorXd(v.tail(na).transpose()) : VectorXd();
      row = inverse_row(model, pose, request.seeds ? &seed : near);
    }
    row.line = table.line_numbers[static_cast<std::size_t>(r)];
    result.failures += !row.ok();
    result.rows.push_back(std::move(row));
  }
  return result;
}

nlohmann::ordered_json kinematics_row_document(bool inverse, const std::string& model_file,
                                               const MeasurementModel& model,
                                               const KinematicsRow& row) {
  nlohmann::ordered_json json = {
      {"format", inverse ? "kincal-ik" : "kincal-fk"}, {"version", 1}, {"model", model_file}};
  json.update(row_json(model, row));
  return json;
}

nlohmann::ordered_json kinematics_solutions_document(const std::string& model_file,
                                                     const MeasurementModel& model,
                                                     const std::vector<KinematicsRow>& solutions) {
  nlohmann::ordered_json json = {{"format", "kincal-ik"},
                                 {"version", 1},
                                 {"model", model_file},
                                 {"solutions", nlohmann::ordered_json::array()}};
  for (const KinematicsRow& s : solutions) json["solutions"].push_back(row_json(model, s));
  return json;
}

std::string forward_row_text(const MeasurementModel& model, const KinematicsRow& row) {
  std::string text =
      format_text("position_mm   %.6f %.6f %.6f\n", row.pose[0], row.pose[1], row.pose[2]);
  text += format_text("rotation_deg  %.6f %.6f %.6f   (rx ry rz, R = Rz(rz) Ry(ry) Rx(rx))\n",
                      row.pose[3], row.pose[4], row.pose[5]);
  const auto names = model.reading_names();
  for (int k = 0; k < row.readings.size(); ++k)
    text +=
        format_text("%-13s %.6f\n", names[static_cast<std::size_t>(k)].c_str(), row.readings[k]);
  return text;
}

std::string inverse_row_text(const MeasurementModel& model, const KinematicsRow& row) {
  std::string text;
  const auto& actuators = model.mechanism().actuators();
  // Micrometres for lengths; for angles nanoradians, a micrometre at a metre's reach.
  for (int i = 0; i < row.actuators.size(); ++i) {
    const auto& actuator = actuators[static_cast<std::size_t>(i)];
    text += format_text(actuator.unit == kRadian ? "%-8s %.9f\n" : "%-8s %.6f\n",
                        actuator.name.c_str(), row.actuators[i]);
  }
  const auto reading_names = model.reading_names();
  for (int k = 0; k < row.readings.size(); ++k)
    text += format_text("%-8s %.6f\n", reading_names[static_cast<std::size_t>(k)].c_str(),
                        row.readings[k]);
  return text;
}

std::string inverse_solutions_text(const MeasurementModel& model,
                                   const std::vector<KinematicsRow>& solutions, bool near_given) {
  std::string text;
  for (std::size_t k = 0; k < solutions.size(); ++k) {
    text += format_text("solution %zu of %zu%s\n", k + 1, solutions.size(),
                        k == 0 ? (near_given ? " (nearest --near)" : " (nearest home)") : "");
    text += inverse_row_text(model, solutions[k]);
  }
  return text;
}

std::string actuator_units_line(const MeasurementModel& model) {
  std::string units;
  for (const auto& a : model.mechanism().actuators())
    units += (units.empty() ? "" : ", ") + a.name + " " + a.unit;
  return "(actuator units: " + units + ")\n";
}

}  // namespace kincal
