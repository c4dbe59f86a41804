#include "kincal/framework/analysis/iso9283.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "kincal/framework/base/format_text.hpp"

namespace kincal {

namespace {

// Mean and sample standard deviation.
void mean_and_std(const std::vector<double>& v, double& mean, double& std) {
  mean = 0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double squares = 0;
  for (double x : v) squares += (x - mean) * (x - mean);
  std = v.size() > 1 ? std::sqrt(squares / static_cast<double>(v.size() - 1)) : 0.0;
}

struct Group {
  int first_row;
  std::vector<Vector3d> measured;
  Vector3d predicted;
};

}  // namespace

Iso9283Stats iso9283_statistics(const MeasurementModel& model, const VectorXd& values,
                                const Measurements& data) {
  Iso9283Stats stats;
  int offset = -1;
  for (std::size_t s = 0; s < model.sensors().size() && offset < 0; ++s) {
    const int index = model.sensors()[s]->position_reading_index();
    if (index >= 0) offset = model.sensor_reading_offset(static_cast<int>(s)) + index;
  }
  if (offset < 0) return stats;
  // The rows of each configuration, in the order configurations first appear.
  std::map<std::vector<double>, int> index_of;
  std::vector<Group> groups;
  auto ws = model.make_workspace();
  VectorXd predicted(model.num_readings());
  for (int r = 0; r < data.size(); ++r) {
    const Vector3d p = data.readings.row(r).segment<3>(offset).transpose();
    if (!p.allFinite()) continue;
    const VectorXd q = data.actuators.row(r).transpose();
    const std::vector<double> key(q.data(), q.data() + q.size());
    auto [it, fresh] = index_of.emplace(key, static_cast<int>(groups.size()));
    if (fresh) {
      if (!model.predict(values, q, predicted, nullptr, ws).ok() ||
          !predicted.segment<3>(offset).allFinite()) {
        index_of.erase(it);
        continue;
      }
      groups.push_back({r, {}, predicted.segment<3>(offset)});
    }
    groups[static_cast<std::size_t>(it->second)].measured.push_back(p);
  }
  std::vector<int> pose_of_group(groups.size(), -1);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const Group& group = groups[g];
    if (group.measured.size() < 2) continue;
    Iso9283Pose pose;
    pose.first_row = group.first_row;
    pose.repeats = static_cast<int>(group.measured.size());
    pose.predicted = group.predicted;
    for (const Vector3d& p : group.measured) pose.barycentre += p / pose.repeats;
    pose.accuracy = (pose.barycentre - pose.predicted).norm();
    std::vector<double> l;
    for (const Vector3d& p : group.measured) l.push_back((p - pose.barycentre).norm());
    double l_mean, l_std;
    mean_and_std(l, l_mean, l_std);
    pose.repeatability = l_mean + 3 * l_std;
    pose_of_group[g] = static_cast<int>(stats.poses.size());
    stats.poses.push_back(pose);
    stats.max_accuracy = std::max(stats.max_accuracy, pose.accuracy);
    stats.max_repeatability = std::max(stats.max_repeatability, pose.repeatability);
  }
  for (std::size_t a = 0; a + 1 < stats.poses.size(); ++a) {
    const std::size_t b = a + 1;
    const Group* ga = nullptr;
    const Group* gb = nullptr;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      if (pose_of_group[g] == static_cast<int>(a)) ga = &groups[g];
      if (pose_of_group[g] == static_cast<int>(b)) gb = &groups[g];
    }
    if (!ga || !gb || ga->measured.size() != gb->measured.size()) continue;
    Iso9283Distance d;
    d.first = static_cast<int>(a);
    d.second = static_cast<int>(b);
    d.repeats = static_cast<int>(ga->measured.size());
    d.commanded = (ga->predicted - gb->predicted).norm();
    std::vector<double> D;
    for (std::size_t j = 0; j < ga->measured.size(); ++j)
      D.push_back((ga->measured[j] - gb->measured[j]).norm());
    double D_mean, D_std;
    mean_and_std(D, D_mean, D_std);
    d.accuracy = D_mean - d.commanded;
    d.repeatability = 3 * D_std;
    stats.distances.push_back(d);
    stats.max_distance_accuracy = std::max(stats.max_distance_accuracy, std::abs(d.accuracy));
    stats.max_distance_repeatability = std::max(stats.max_distance_repeatability, d.repeatability);
  }
  return stats;
}

namespace {

int line_of(const std::vector<int>& lines, int row) {
  return row < static_cast<int>(lines.size()) ? lines[static_cast<std::size_t>(row)] : row + 1;
}

}  // namespace

std::string iso9283_text(const Iso9283Stats& stats, const std::vector<int>& lines, int shown) {
  std::ostringstream out;
  out << format_text(
      "ISO 9283, %zu repeated configurations (command = the model's prediction), mm:\n",
      stats.poses.size());
  out << format_text("  pose accuracy AP max %.4g, repeatability RP max %.4g\n", stats.max_accuracy,
                     stats.max_repeatability);
  if (!stats.distances.empty())
    out << format_text(
        "  distance accuracy |AD| max %.4g, repeatability RD max %.4g (%zu pairs of "
        "consecutive poses)\n",
        stats.max_distance_accuracy, stats.max_distance_repeatability, stats.distances.size());
  int count = 0;
  for (const Iso9283Pose& p : stats.poses) {
    if (count++ >= shown) {
      out << format_text("  ... %zu more in the JSON (iso9283)\n",
                         stats.poses.size() - static_cast<std::size_t>(shown));
      break;
    }
    out << format_text("  line %-5d n %-3d AP %-9.4g RP %-9.4g\n", line_of(lines, p.first_row),
                       p.repeats, p.accuracy, p.repeatability);
  }
  return out.str();
}

nlohmann::ordered_json iso9283_json(const Iso9283Stats& stats, const std::vector<int>& lines) {
  using Json = nlohmann::ordered_json;
  const auto vec = [](const Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); };
  Json poses = Json::array();
  for (const Iso9283Pose& p : stats.poses)
    poses.push_back({{"line", line_of(lines, p.first_row)},
                     {"repeats", p.repeats},
                     {"predicted_mm", vec(p.predicted)},
                     {"barycentre_mm", vec(p.barycentre)},
                     {"ap_mm", p.accuracy},
                     {"rp_mm", p.repeatability}});
  Json distances = Json::array();
  for (const Iso9283Distance& d : stats.distances)
    distances.push_back(
        {{"first", line_of(lines, stats.poses[static_cast<std::size_t>(d.first)].first_row)},
         {"second", line_of(lines, stats.poses[static_cast<std::size_t>(d.second)].first_row)},
         {"repeats", d.repeats},
         {"commanded_mm", d.commanded},
         {"ad_mm", d.accuracy},
         {"rd_mm", d.repeatability}});
  return {{"max_ap_mm", stats.max_accuracy},
          {"max_rp_mm", stats.max_repeatability},
          {"max_ad_mm", stats.max_distance_accuracy},
          {"max_rd_mm", stats.max_distance_repeatability},
          {"poses", poses},
          {"distances", distances}};
}

}  // namespace kincal
