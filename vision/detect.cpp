#include "kincal/vision/detect.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/models/flange_pose.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal::vision {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

bool is_number(const std::string& field) {
  if (field.empty()) return false;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);
  return end == field.c_str() + field.size() && std::isfinite(value);
}

// Natural order: digit runs compared as numbers ("2.png" before "10.png").
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      const std::string na = a.substr(i, ei - i), nb = b.substr(j, ej - j);
      const std::string ta = na.substr(std::min(na.find_first_not_of('0'), na.size()));
      const std::string tb = nb.substr(std::min(nb.find_first_not_of('0'), nb.size()));
      if (ta.size() != tb.size()) return ta.size() < tb.size();
      if (ta != tb) return ta < tb;
      i = ei;
      j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

bool is_image_file(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* known : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm"})
    if (ext == known) return true;
  return false;
}

}  // namespace

ImagePoses read_image_poses(const std::string& path, const std::string& images_folder) {
  std::error_code error;
  if (fs::is_directory(path, error))
    throw std::invalid_argument(path + ": a folder, expected the poses file (CSV)");
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot open the poses file");
  const fs::path folder =
      images_folder.empty() ? fs::path(path).parent_path() : fs::path(images_folder);
  return parse_image_poses(in, path, folder.string(), true);
}

ImagePoses parse_image_poses(std::istream& in, const std::string& path,
                             const std::string& folder_name, bool require_images) {
  const fs::path folder(folder_name);
  ImagePoses poses;
  std::string line;
  int number = 0, image_column = -1;
  std::vector<std::string> header;
  std::set<std::string> seen;
  while (std::getline(in, line)) {
    ++number;
    if (line.size() > (std::size_t{64} << 10))
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": line too long");
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> fields = split_fields(t);
    const std::string at = path + ":" + std::to_string(number);
    if (header.empty()) {
      header = fields;
      if (!header.empty() && header[0].rfind("\xEF\xBB\xBF", 0) == 0) header[0].erase(0, 3);
      for (std::size_t c = 0; c < header.size(); ++c) {
        if (header[c] == "image") {
          if (image_column >= 0)
            throw std::invalid_argument(at + ": the column 'image' appears twice");
          image_column = static_cast<int>(c);
        } else {
          if (header[c].empty()) throw std::invalid_argument(at + ": an empty column name");
          poses.columns.push_back(header[c]);
        }
      }
      if (image_column < 0)
        throw std::invalid_argument(at + ": no column 'image' (the image file of each row)");
      continue;
    }
    if (fields.size() != header.size())
      throw std::invalid_argument(at + ": " + std::to_string(fields.size()) + " fields, expected " +
                                  std::to_string(header.size()) + " as in the header");
    const std::string& image = fields[static_cast<std::size_t>(image_column)];
    if (image.empty()) throw std::invalid_argument(at + ": the image is empty");
    if (image.find('"') != std::string::npos)
      throw std::invalid_argument(at + ": image '" + message_excerpt(image) +
                                  "': a file name without quotes expected");
    if (!seen.insert(image).second)
      throw std::invalid_argument(at + ": image '" + message_excerpt(image) + "' is named twice");
    std::vector<std::string> values;
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (static_cast<int>(c) == image_column) continue;
      if (!is_number(fields[c]))
        throw std::invalid_argument(at + ": column '" + message_excerpt(header[c]) + "': '" +
                                    message_excerpt(fields[c]) + "' is not a number");
      values.push_back(fields[c]);
    }
    const std::string image_path =
        fs::path(image).is_absolute() ? image : (folder / image).string();
    std::error_code error;
    if (require_images && !fs::is_regular_file(image_path, error))
      throw std::invalid_argument(at + ": image '" + message_excerpt(image) + "': no such file (" +
                                  message_excerpt(image_path) + ")");
    poses.images.push_back(image);
    poses.paths.push_back(image_path);
    poses.values.push_back(std::move(values));
    poses.lines.push_back(number);
  }
  if (in.bad()) throw std::invalid_argument(path + ": read error");
  if (header.empty()) throw std::invalid_argument(path + ": empty, expected a header row");
  if (poses.images.empty()) throw std::invalid_argument(path + ": no rows after the header");
  return poses;
}

ImagePoses images_in_folder(const std::string& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error))
    throw std::invalid_argument(folder + ": not a folder of images");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder, error))
    if (entry.is_regular_file() && is_image_file(entry.path()))
      names.push_back(entry.path().filename().string());
  if (error) throw std::invalid_argument(folder + ": " + error.message());
  if (names.empty())
    throw std::invalid_argument(folder +
                                ": no image files (png, jpg, jpeg, bmp, tif, tiff, pgm, ppm)");
  std::sort(names.begin(), names.end(), natural_less);
  ImagePoses poses;
  for (const auto& name : names) {
    poses.images.push_back(name);
    poses.paths.push_back((fs::path(folder) / name).string());
    poses.values.emplace_back();
    poses.lines.push_back(0);
  }
  return poses;
}

int DetectResult::found() const {
  int n = 0;
  for (const auto& r : records) n += r.detection.status == DetectionStatus::kFound;
  return n;
}

DetectResult detect_images(const DetectRequest& request) {
  DetectResult result;
  result.total = static_cast<int>(request.images.paths.size());
  for (std::size_t k = 0; k < request.images.paths.size(); ++k) {
    if (request.stop_requested && request.stop_requested()) {
      result.interrupted = true;
      break;
    }
    ImageRecord record{request.images.images[k],
                       detect_target(request.images.paths[k], request.target, request.options)};
    Detection& d = record.detection;
    if (d.width > 0 && result.width == 0) {
      result.width = d.width;
      result.height = d.height;
    } else if (d.width > 0 && (d.width != result.width || d.height != result.height)) {
      d.status = DetectionStatus::kRejected;
      d.reason = format_text(
          "%d x %d px, not the %d x %d px of the first image (one camera, "
          "one image size)",
          d.width, d.height, result.width, result.height);
    }
    result.records.push_back(std::move(record));
    if (request.on_image) request.on_image(static_cast<int>(k + 1));
  }
  return result;
}

std::string DetectResult::csv(const DetectRequest& request) const {
  std::ostringstream out;
  out << "# kincal detect: target " << request.target.text << ", " << found() << " of " << total
      << " images" << (interrupted ? " (interrupted)" : "") << ", " << width << " x " << height
      << " px\n";
  out << "image";
  for (const auto& column : request.images.columns) out << ',' << column;
  const CameraTarget target = request.target.camera_target();
  for (const auto& name : target.names)
    out << ',' << request.camera_name << '.' << name << ".u," << request.camera_name << '.' << name
        << ".v";
  out << '\n';
  for (std::size_t k = 0; k < records.size(); ++k) {
    const Detection& d = records[k].detection;
    if (d.status != DetectionStatus::kFound) continue;
    out << records[k].image;
    for (const auto& value : request.images.values[k]) out << ',' << value;
    for (const auto& p : d.points) {
      if (std::isfinite(p.x()))
        out << format_text(",%.4f,%.4f", p.x(), p.y());
      else
        out << ",,";
    }
    out << '\n';
  }
  return out.str();
}

std::string DetectResult::text() const {
  std::size_t width_of_name = 5;
  for (const auto& r : records) width_of_name = std::max(width_of_name, r.image.size());
  std::ostringstream out;
  out << format_text("%-*s  %-10s  %6s  %10s  %s\n", static_cast<int>(width_of_name), "image",
                     "status", "points", "homography", "reason");
  for (const auto& r : records) {
    const Detection& d = r.detection;
    const std::string rms =
        d.found >= 4 ? format_text("%.3f px", d.homography_rms_px) : std::string("-");
    out << format_text("%-*s  %-10s  %6d  %10s  %s\n", static_cast<int>(width_of_name),
                       r.image.c_str(), to_string(d.status), d.found, rms.c_str(),
                       d.reason.c_str());
  }
  out << format_text("%d of %d images with the target", found(), total);
  if (interrupted)
    out << format_text(" (interrupted after %d images: the rest not looked at)",
                       static_cast<int>(records.size()));
  out << '\n';
  return out.str();
}

nlohmann::ordered_json DetectResult::json() const {
  nlohmann::ordered_json j;
  j["images"] = nlohmann::ordered_json::array();
  for (const auto& r : records) {
    const Detection& d = r.detection;
    nlohmann::ordered_json image{
        {"image", r.image}, {"status", to_string(d.status)}, {"points", d.found}};
    image["homography_rms_px"] = d.found >= 4 && std::isfinite(d.homography_rms_px)
                                     ? nlohmann::ordered_json(d.homography_rms_px)
                                     : nlohmann::ordered_json(nullptr);
    image["reason"] = d.reason;
    j["images"].push_back(image);
  }
  j["found"] = found();
  j["total"] = total;
  j["interrupted"] = interrupted;
  j["width"] = width;
  j["height"] = height;
  return j;
}

namespace {

// The flange-pose mechanism for the data in `table` (read with a flange-pose mechanism's
// columns): home at the first view's pose (the camera sees the target there), the box
// around it as wide as the data.
std::shared_ptr<const Mechanism> flange_pose_for(const MeasurementTable& table) {
  const Vector6d home = table.data.actuators.row(0).transpose();
  double position = 10, rotation = 0.05;  // mm, rad: at least
  for (int r = 0; r < table.data.size(); ++r) {
    const Vector6d q = table.data.actuators.row(r).transpose();
    position = std::max(position, (q.head<3>() - home.head<3>()).cwiseAbs().maxCoeff());
    rotation = std::max(rotation, (q.tail<3>() - home.tail<3>()).cwiseAbs().maxCoeff());
  }
  Pose pose;
  pose.translation = home.head<3>();
  pose.rotation = exp_so3(home.tail<3>());
  return std::make_shared<FlangePose>(pose, position, std::min(rotation, 3.0));
}

void set_default_mask(MeasurementModel& model, const std::string& camera) {
  ParameterSet& parameters = model.parameters();
  for (const char* free : {".frame.*", ".target.*", ".f?", ".c?", ".k1", ".k2", ".p?"})
    parameters.set_free(camera + free, true);
}

}  // namespace

StartResult start_model(const DetectRequest& request, const DetectResult& result,
                        const StartRequest& start) {
  StartResult out;
  if (result.found() == 0) throw std::invalid_argument("no image with the target");
  CameraIntrinsics intrinsics;
  if (start.intrinsics) {
    intrinsics = *start.intrinsics;
  } else {
    std::vector<Detection> detections;
    for (const auto& r : result.records) detections.push_back(r.detection);
    out.intrinsics = calibrate_intrinsics(detections, request.target, result.width, result.height);
    if (!out.intrinsics.ok) throw std::invalid_argument(out.intrinsics.reason);
    intrinsics = out.intrinsics.intrinsics;
  }
  auto camera = std::make_shared<Camera>(request.camera_name, start.mounting,
                                         request.target.camera_target(), Vector6d::Zero(),
                                         Vector6d::Zero(), intrinsics, result.width, result.height);
  auto mechanism =
      start.mechanism ? start.mechanism : std::make_shared<FlangePose>(Pose(), 100.0, 0.35);
  // The table as calibrate will read it: the mechanism's columns, units converted.
  const auto read_table = [&](const MeasurementModel& model) {
    std::istringstream csv(result.csv(request));
    try {
      MeasurementTable table = parse_measurements(
          csv, "the detected table", model.mechanism().actuator_names(), model.reading_names());
      std::vector<std::string> actuator_units;
      for (const auto& a : model.mechanism().actuators()) actuator_units.push_back(a.unit);
      convert_column_units(table, actuator_units, model.reading_units(), "the detected table");
      return table;
    } catch (const std::invalid_argument& e) {
      std::string expected;
      for (const auto& name : model.mechanism().actuator_names())
        expected += (expected.empty() ? "" : ", ") + name;
      throw std::invalid_argument(std::string("the poses file's columns are not the ") +
                                  model.mechanism().type() + " mechanism's (" + expected +
                                  ", each may carry a unit suffix): " + e.what());
    }
  };
  auto model = std::make_shared<MeasurementModel>(
      mechanism, std::vector<std::shared_ptr<const Sensor>>{camera});
  MeasurementTable table = read_table(*model);
  if (!start.mechanism) {
    mechanism = flange_pose_for(table);
    model = std::make_shared<MeasurementModel>(mechanism,
                                               std::vector<std::shared_ptr<const Sensor>>{camera});
  }
  const VectorXd values = model->parameters().nominal_values();
  out.mounts = estimate_camera_mounts(*model, 0, values, table.data);
  if (!out.mounts.ok) throw std::invalid_argument("the camera's mounts: " + out.mounts.reason);
  VectorXd start_values = values;
  const int offset = model->sensor_parameter_offset(0);
  start_values.segment<6>(offset + Camera::kFrameIndex) = out.mounts.frame;
  start_values.segment<6>(offset + Camera::kTargetIndex) = out.mounts.target;
  out.model = model_with_values(*model, start_values);
  set_default_mask(*out.model, request.camera_name);
  out.model_text = model_to_json(*out.model, start_values).dump(2) + "\n";
  return out;
}

DetectOutputs detect_outputs(const DetectRequest& request, const DetectResult& result,
                             const std::optional<StartRequest>& start) {
  DetectOutputs out;
  if (result.found() > 0) out.csv = result.csv(request);
  if (start && result.found() > 0 && !result.interrupted) {
    try {
      const StartResult started = start_model(request, result, *start);
      out.model_text = started.model_text;
      out.start_text = started.text();
    } catch (const std::invalid_argument& e) {
      out.start_error = e.what();
    }
  }
  out.json = {{"format", "kincal-detect"}, {"version", 1}};
  out.json.update(result.json());
  return out;
}

std::string StartResult::text() const {
  std::ostringstream out;
  if (intrinsics.ok)
    out << format_text(
        "intrinsics from OpenCV's calibrateCamera on %d views (%.3f px RMS): fx "
        "%.2f, fy %.2f, cx %.2f, cy %.2f px\n",
        intrinsics.views, intrinsics.rms_px, intrinsics.intrinsics.fx, intrinsics.intrinsics.fy,
        intrinsics.intrinsics.cx, intrinsics.intrinsics.cy);
  out << format_text(
      "mounts from the hand-eye solution of %d views (%d motions turning enough): "
      "the motions agree to %.4f rad and %.3f mm RMS\n",
      mounts.views_used, mounts.hand_eye.motions_used, mounts.hand_eye.rotation_rms,
      mounts.hand_eye.translation_rms);
  return out.str();
}

}  // namespace kincal::vision
