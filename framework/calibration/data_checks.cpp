#include "kincal/framework/calibration/data_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include "kincal/framework/base/parallel.hpp"
#include "kincal/framework/kinematics/pose.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal {

namespace {

std::string format(const char* fmt, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, a);
  return buf;
}

double rotation_angle(const Matrix3d& a, const Matrix3d& b) {
  return log_so3(a.transpose() * b).norm();
}

// Rows per chunk of the per-row passes, which run in parallel (base/parallel.hpp).
constexpr int kRowsPerChunk = 4096;
// Rows check_data_units predicts at most.
constexpr int kUnitSampleRows = 10000;

}  // namespace

HomePoseCheck check_poses_near_home(const MeasurementModel& model, const VectorXd& params,
                                    const Measurements& data) {
  HomePoseCheck check;
  const Mechanism& mechanism = model.mechanism();
  // Closed form forward kinematics (a serial arm) has one answer whatever the start.
  if (!mechanism.forward_kinematics_has_assemblies()) return check;
  const Pose& home = mechanism.home_pose();
  const auto mechanism_params = params.head(static_cast<int>(mechanism.parameters().size()));
  std::vector<ForwardKinematicsResult> reached(static_cast<std::size_t>(data.size()));
  parallel_chunks(data.size(), kRowsPerChunk, [&](int, int begin, int end) {
    for (int row = begin; row < end; ++row)
      reached[static_cast<std::size_t>(row)] =
          mechanism.forward_kinematics(mechanism_params, data.actuators.row(row).transpose(), home,
                                       model.forward_kinematics_options());
  });
  std::vector<Pose> poses;
  for (const ForwardKinematicsResult& fk : reached)
    if (fk.ok()) poses.push_back(fk.pose);
  check.poses = static_cast<int>(poses.size());
  if (poses.empty()) return check;
  Vector3d centre = Vector3d::Zero();
  for (const Pose& p : poses) centre += p.translation;
  centre /= static_cast<double>(poses.size());
  std::size_t central = 0;
  check.nearest_position_mm = check.nearest_angle_rad = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double from_centre = (poses[i].translation - centre).norm();
    check.extent_mm = std::max(check.extent_mm, from_centre);
    if (from_centre < (poses[central].translation - centre).norm()) central = i;
    check.nearest_position_mm =
        std::min(check.nearest_position_mm, (poses[i].translation - home.translation).norm());
    check.nearest_angle_rad =
        std::min(check.nearest_angle_rad, rotation_angle(home.rotation, poses[i].rotation));
  }
  for (const Pose& p : poses)
    check.extent_angle_rad =
        std::max(check.extent_angle_rad, rotation_angle(poses[central].rotation, p.rotation));
  const bool far_position = check.nearest_position_mm > std::max(check.extent_mm, kHomeFarMm);
  const bool far_rotation = check.nearest_angle_rad > std::max(check.extent_angle_rad, kHomeFarRad);
  check.far = far_position || far_rotation;
  if (check.far)
    check.warning =
        "forward kinematics of the data lands far from the model's home_pose: the closest of " +
        std::to_string(check.poses) + " poses is " + format("%.4g", check.nearest_position_mm) +
        " mm and " + format("%.3g", check.nearest_angle_rad * 180 / M_PI) +
        " deg from it, while the poses themselves spread over " + format("%.4g", check.extent_mm) +
        " mm and " + format("%.3g", check.extent_angle_rad * 180 / M_PI) +
        " deg. Forward kinematics starts at home_pose and converges to the nearest assembly of "
        "the mechanism, so a wrong home_pose silently gives other valid poses: check home_pose "
        "against the machine (kincal fk on a row whose pose you know)";
  return check;
}

std::string encoder_stroke_hint(const MeasurementModel& model, const VectorXd& params,
                                const Measurements& data, int failed_rows) {
  if (data.size() == 0 || 2 * failed_rows < data.size()) return "";
  const Mechanism& mechanism = model.mechanism();
  const auto mechanism_params = params.head(static_cast<int>(mechanism.parameters().size()));
  VectorXd home_q(static_cast<int>(mechanism.actuators().size()));
  if (!mechanism.home_actuators(mechanism_params, home_q).ok()) return "";
  int lengths = 0, short_ones = 0;
  double example_value = 0, example_home = 0;
  std::string example;
  for (int a = 0; a < home_q.size(); ++a) {
    if (mechanism.actuators()[a].unit != kMillimetre || !(std::abs(home_q[a]) > 0)) continue;
    std::vector<double> magnitudes;
    for (int row = 0; row < data.size(); ++row)
      if (std::isfinite(data.actuators(row, a)))
        magnitudes.push_back(std::abs(data.actuators(row, a)));
    if (magnitudes.empty()) continue;
    std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                     magnitudes.end());
    const double median = magnitudes[magnitudes.size() / 2];
    ++lengths;
    if (median < 0.25 * std::abs(home_q[a])) {
      ++short_ones;
      if (example.empty()) {
        example = mechanism.actuators()[a].name;
        example_value = median;
        example_home = home_q[a];
      }
    }
  }
  if (lengths == 0 || 2 * short_ones <= lengths) return "";
  return "the actuator values look like encoder strokes, not lengths (median |" + example +
         "| is " + format("%.4g", example_value) + " mm, while the model's " + example + " is " +
         format("%.4g", example_home) +
         " mm long at home): the model reads a length as value + offset, so set each "
         "actuator's offset in the model file to its length at the encoder's zero (measure it "
         "once, or compute it with kincal ik at a known pose), then free the offsets to refine "
         "them (e.g. --free '" +
         example + ".offset')";
}

namespace {

// "a, b and c" (at most `max` names, then "and N more").
std::string name_list(const std::vector<std::string>& names, std::size_t max = 6) {
  std::string out;
  const std::size_t shown = std::min(names.size(), max);
  for (std::size_t i = 0; i < shown; ++i)
    out += (i == 0 ? "" : i + 1 == shown && shown == names.size() ? " and " : ", ") + names[i];
  if (shown < names.size()) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

std::vector<std::string> with_suffix(const std::vector<std::string>& names,
                                     const std::string& suffix) {
  std::vector<std::string> out;
  for (const auto& n : names) out.push_back(n + "_" + suffix);
  return out;
}

// Angle columns without a suffix whose values go beyond one turn.
std::string angle_hint(const std::vector<std::string>& names, double lo, double hi,
                       const char* what) {
  return std::string(what) + " " + name_list(names) + " span " + format("%.4g", lo) + " .. " +
         format("%.4g", hi) +
         ", beyond one turn (+-6.283 rad), which looks like degrees where the model takes "
         "radians; name the columns " +
         name_list(with_suffix(names, "deg")) + " (or convert them to radians)";
}

// The spread of each sensor's length readings against the spread the model predicts at the
// same configurations: the sensor's frame, where it is mounted and where the measured point
// is do not change it (a point's spread about its centre is the same in every frame), so a
// unit mistake shows whatever the starting values, even where the residuals at the start are
// dominated by an unknown frame. A point sensor's three readings are one point; other length
// readings are compared one by one. Rows as in check_data_units (every stride-th).
std::string spread_mismatch(const MeasurementModel& model, const VectorXd& params,
                            const Measurements& data, int stride) {
  const auto units = model.reading_units();
  const auto names = model.reading_names();
  const int k = model.num_readings();
  // Groups of readings: a point (three) or a single length reading.
  std::vector<std::vector<int>> groups;
  for (std::size_t s = 0; s < model.sensors().size(); ++s) {
    const Sensor& sensor = *model.sensors()[s];
    const int o = model.sensor_reading_offset(static_cast<int>(s));
    const int point = sensor.position_reading_index();
    for (int i = 0; i < sensor.num_readings(); ++i) {
      if (units[o + i] != kMillimetre) continue;
      if (point >= 0 && i >= point && i < point + 3) {
        if (i == point) groups.push_back({o + i, o + i + 1, o + i + 2});
        continue;
      }
      groups.push_back({o + i});
    }
  }
  if (groups.empty()) return "";
  std::vector<VectorXd> measured, predicted;
  auto ws = model.make_workspace();
  VectorXd p(k);
  for (int r = 0; r < data.size(); r += stride) {
    if (!model.predict(params, data.actuators.row(r).transpose(), p, nullptr, ws).ok() ||
        !p.allFinite())
      continue;
    measured.push_back(data.readings.row(r).transpose());
    predicted.push_back(p);
  }
  for (const auto& group : groups) {
    // Spread about the centre, over the rows where the group was measured: the median
    // distance from the component-wise median, so that one wild reading (1e308) is the
    // residual check's to name by its line, not a units verdict on the whole file.
    const auto spread = [&](const std::vector<VectorXd>& rows) {
      std::vector<std::size_t> present;
      for (std::size_t r = 0; r < rows.size(); ++r)
        if (!std::isnan(measured[r][group[0]])) present.push_back(r);
      if (present.size() < 3) return std::numeric_limits<double>::quiet_NaN();
      const auto median = [](std::vector<double>& values) {
        const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
        std::nth_element(values.begin(), middle, values.end());
        return *middle;
      };
      std::vector<double> values(present.size());
      VectorXd centre(static_cast<int>(group.size()));
      for (std::size_t g = 0; g < group.size(); ++g) {
        for (std::size_t i = 0; i < present.size(); ++i) values[i] = rows[present[i]][group[g]];
        centre[static_cast<int>(g)] = median(values);
      }
      for (std::size_t i = 0; i < present.size(); ++i) {
        double sum = 0;
        for (std::size_t g = 0; g < group.size(); ++g)
          sum += std::pow(rows[present[i]][group[g]] - centre[static_cast<int>(g)], 2);
        values[i] = std::sqrt(sum);
      }
      return median(values);
    };
    const double seen = spread(measured), expected = spread(predicted);
    // Readings that do not move, or configurations that hardly move the point (a thousandth
    // of its distance from the sensor: repeats of one configuration, whose readings spread
    // by their noise alone): nothing to compare.
    double magnitude = 0;
    int counted = 0;
    for (const VectorXd& p : predicted)
      for (int g : group) {
        magnitude += p[g] * p[g];
        ++counted;
      }
    magnitude = counted ? std::sqrt(magnitude * static_cast<double>(group.size()) / counted) : 0;
    if (!(seen > 0) || !(expected > 1e-3 * magnitude)) continue;
    const double ratio = seen / expected;
    if (ratio > 1.0 / kSpreadMismatch && ratio < kSpreadMismatch) continue;
    std::string columns;
    for (std::size_t g = 0; g < group.size(); ++g) columns += (g ? ", " : "") + names[group[g]];
    const bool metres = ratio > 1.0 / 3000 && ratio < 1.0 / 300;
    return "the readings " + columns + " spread over " + format("%.4g", seen) +
           " mm (median distance from their median), while the model predicts " +
           format("%.4g", expected) + " mm at the same configurations: " + format("%.3g", ratio) +
           " times" +
           (metres ? ", which looks like metres where the model takes millimetres; name the "
                     "columns " +
                         name_list(
                             with_suffix(std::vector<std::string>(names.begin() + group.front(),
                                                                  names.begin() + group.back() + 1),
                                         "m")) +
                         " (or convert them to millimetres)"
                   : "; expected readings of this machine in millimetres (check the columns' "
                     "units, that the data belong to this model, and the model's lengths)");
  }
  return "";
}

}  // namespace

std::string check_data_units(const MeasurementModel& model, const VectorXd& params,
                             const MeasurementTable& table) {
  const Mechanism& mechanism = model.mechanism();
  const int na = mechanism.num_actuators();
  const Measurements& data = table.data;
  if (data.actuators.cols() != na || data.size() == 0) return "";
  const auto suffixed = [&](int column) {
    return column < static_cast<int>(table.column_units.size()) &&
           !table.column_units[column].empty();
  };
  constexpr double kTurn = 2 * M_PI * (1 + 1e-9);

  // Revolute joints: beyond one turn is degrees.
  std::vector<std::string> angles;
  double lo = 0, hi = 0;
  bool beyond = false;
  for (int a = 0; a < na; ++a) {
    if (mechanism.actuators()[a].unit != kRadian || suffixed(a)) continue;
    angles.push_back(mechanism.actuators()[a].name);
    lo = std::min(lo, data.actuators.col(a).minCoeff());
    hi = std::max(hi, data.actuators.col(a).maxCoeff());
    beyond = beyond || data.actuators.col(a).cwiseAbs().maxCoeff() > kTurn;
  }
  if (beyond) return angle_hint(angles, lo, hi, "the joint (actuator) columns");

  // Length actuators about a thousandth of their length at home: metres.
  const auto mechanism_params = params.head(mechanism.num_parameters());
  VectorXd home(na);
  if (mechanism.home_actuators(mechanism_params, home).ok()) {
    std::vector<std::string> lengths;
    int metres = 0;
    double first_home = 0;
    for (int a = 0; a < na; ++a) {
      if (mechanism.actuators()[a].unit != kMillimetre || suffixed(a) || !(std::abs(home[a]) > 0))
        continue;
      std::vector<double> ratio;
      for (int r = 0; r < data.size(); ++r)
        ratio.push_back(std::abs(data.actuators(r, a)) / std::abs(home[a]));
      std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
      const double median = ratio[ratio.size() / 2];
      if (lengths.empty()) first_home = std::abs(home[a]);
      lengths.push_back(mechanism.actuators()[a].name);
      metres += median > 1.0 / 3000 && median < 1.0 / 300;
    }
    if (!lengths.empty() && 2 * metres > static_cast<int>(lengths.size()))
      return "the length actuator columns " + name_list(lengths) +
             " are about a thousandth of the model's lengths at home (" +
             format("%.4g", first_home) +
             " mm for the first), which looks like metres where the model takes millimetres; "
             "name the columns " +
             name_list(with_suffix(lengths, "m")) + " (or convert them to millimetres)";
  }

  // Readings: angles beyond a turn are degrees; lengths that fit 1000 times better scaled
  // by 1000 are metres.
  const int k = model.num_readings();
  if (data.readings.cols() != k || k == 0) return "";
  const auto units = model.reading_units();
  const auto names = model.reading_names();
  std::vector<std::string> angle_readings;
  lo = hi = 0;
  beyond = false;
  for (int i = 0; i < k; ++i) {
    if (units[i] != kRadian || suffixed(na + i)) continue;
    angle_readings.push_back(names[i]);
    for (int r = 0; r < data.size(); ++r) {
      const double v = data.readings(r, i);
      if (std::isnan(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      beyond = beyond || std::abs(v) > kTurn;
    }
  }
  if (beyond) return angle_hint(angle_readings, lo, hi, "the angle reading columns");

  std::vector<int> mm_readings;
  for (int i = 0; i < k; ++i)
    if (units[i] == kMillimetre && !suffixed(na + i)) mm_readings.push_back(i);
  // A ratio of RMS errors is decided by any ten thousand rows as well as by all: on larger
  // data every stride-th row is predicted (10^6 rows: 1.4 s of forward kinematics saved).
  const int stride = std::max(1, data.size() / kUnitSampleRows);
  if (mm_readings.empty()) return spread_mismatch(model, params, data, stride);
  const int sampled = (data.size() + stride - 1) / stride;
  // Sums per chunk of rows, added in chunk order.
  struct Sums {
    double as_given = 0, scaled = 0;
    long count = 0;
  };
  std::vector<Sums> sums(static_cast<std::size_t>(chunk_count(sampled, kRowsPerChunk)));
  parallel_chunks(sampled, kRowsPerChunk, [&](int chunk, int begin, int end) {
    auto ws = model.make_workspace();
    VectorXd predicted(k);
    Sums& sum = sums[static_cast<std::size_t>(chunk)];
    for (int sample = begin; sample < end; ++sample) {
      const int r = sample * stride;
      if (!model.predict(params, data.actuators.row(r).transpose(), predicted, nullptr, ws).ok() ||
          !predicted.allFinite())
        continue;
      for (int i : mm_readings) {
        const double v = data.readings(r, i);
        if (std::isnan(v)) continue;
        sum.as_given += (predicted[i] - v) * (predicted[i] - v);
        sum.scaled += (predicted[i] - 1000 * v) * (predicted[i] - 1000 * v);
        ++sum.count;
      }
    }
  });
  double as_given = 0, scaled = 0;
  long count = 0;
  for (const Sums& sum : sums) {
    as_given += sum.as_given;
    scaled += sum.scaled;
    count += sum.count;
  }
  if (count == 0) return spread_mismatch(model, params, data, stride);
  as_given = std::sqrt(as_given / count);
  scaled = std::sqrt(scaled / count);
  if (!(scaled < 0.1 * as_given)) return spread_mismatch(model, params, data, stride);
  std::vector<std::string> columns;
  for (int i : mm_readings) columns.push_back(names[i]);
  return "the length reading columns " + name_list(columns) +
         " look like metres where the model takes millimetres: multiplied by 1000 they are " +
         format("%.4g", scaled) + " mm RMS from the model's predictions, as given " +
         format("%.4g", as_given) + " mm; name the columns " +
         name_list(with_suffix(columns, "m")) + " (or convert them to millimetres)";
}

namespace {

// Bit patterns of a row's values, so that equal means identical (NaN, a missing reading,
// equals itself; -0 and 0 differ, as two instruments' outputs would).
std::vector<std::uint64_t> bits_of(const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  std::vector<std::uint64_t> bits(static_cast<std::size_t>(row.size()));
  for (Eigen::Index i = 0; i < row.size(); ++i) {
    const double value = row[i];
    std::memcpy(&bits[static_cast<std::size_t>(i)], &value, sizeof(double));
  }
  return bits;
}

struct BitsHash {
  std::size_t operator()(const std::vector<std::uint64_t>& bits) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint64_t b : bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

Repeats find_repeats(const Measurements& data) {
  Repeats out;
  // Configuration -> its distinct rows (by their readings), first occurrence each.
  std::unordered_map<std::vector<std::uint64_t>, std::vector<int>, BitsHash> at;
  at.reserve(static_cast<std::size_t>(data.size()));
  for (int r = 0; r < data.size(); ++r) {
    std::vector<int>& rows = at[bits_of(data.actuators.row(r))];
    const std::vector<std::uint64_t> readings = bits_of(data.readings.row(r));
    int copy_of = -1;
    for (int earlier : rows)
      if (bits_of(data.readings.row(earlier)) == readings) {
        copy_of = earlier;
        break;
      }
    if (copy_of >= 0) {
      out.duplicates.push_back(r);
      out.duplicate_of.push_back(copy_of);
    } else {
      rows.push_back(r);
    }
  }
  for (const auto& [configuration, rows] : at)
    if (rows.size() > 1) {
      ++out.repeated_configurations;
      out.repeat_rows += static_cast<int>(rows.size());
    }
  return out;
}

}  // namespace kincal
