#include "kincal/models/camera_views.hpp"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "kincal/framework/calibration/measurement_file.hpp"
#include "kincal/models/camera.hpp"

namespace kincal {

bool has_camera(const MeasurementModel& model) {
  for (const auto& sensor : model.sensors())
    if (dynamic_cast<const Camera*>(sensor.get())) return true;
  return false;
}

ImageViews camera_image_views(const MeasurementModel& model, int sensor_index,
                              const Eigen::Ref<const VectorXd>& params, const Measurements& data,
                              const std::vector<std::string>& labels,
                              const std::vector<std::string>& images) {
  const auto* camera = dynamic_cast<const Camera*>(model.sensors().at(sensor_index).get());
  if (!camera) throw std::invalid_argument("camera_image_views: the sensor is not a camera");
  ImageViews out;
  out.sensor = camera->name();
  out.width = camera->image_width();
  out.height = camera->image_height();
  const int offset = model.sensor_reading_offset(sensor_index);
  auto ws = model.make_workspace();
  VectorXd predicted(model.num_readings());
  for (int row = 0; row < data.size(); ++row) {
    const auto measured = data.readings.row(row).segment(offset, camera->num_readings());
    if (measured.array().isNaN().all()) continue;
    const VectorXd q = data.actuators.row(row).transpose();
    if (!model.predict(params, q, predicted, nullptr, ws).ok()) continue;
    const auto own = predicted.segment(offset, camera->num_readings());
    if (own.hasNaN()) continue;  // the camera does not read there
    ImageView view;
    view.label =
        row < static_cast<int>(labels.size()) ? labels[row] : "row " + std::to_string(row + 1);
    if (row < static_cast<int>(images.size())) view.image = images[row];
    for (int p = 0; p < camera->num_points(); ++p) {
      if (std::isnan(measured[2 * p]) || std::isnan(measured[2 * p + 1])) continue;
      view.measured.emplace_back(measured[2 * p], measured[2 * p + 1]);
      view.predicted.emplace_back(own[2 * p], own[2 * p + 1]);
    }
    out.views.push_back(std::move(view));
  }
  summarise_image_views(out);
  return out;
}

std::vector<std::string> images_of_rows(const std::string& data_file,
                                        const std::vector<int>& lines) {
  const std::map<int, std::string> column = read_csv_text_column(data_file, "image");
  std::vector<std::string> images;
  if (column.empty()) return images;
  for (int line : lines) {
    const auto it = column.find(line);
    images.push_back(it == column.end() ? std::string() : it->second);
  }
  return images;
}

CameraViewChecks calibration_camera_views(const MeasurementModel& model,
                                          const Eigen::Ref<const VectorXd>& params,
                                          const LoadedMeasurements& data,
                                          const std::string& data_file) {
  if (!has_camera(model)) return {};
  std::vector<std::string> labels;
  for (int line : data.lines) labels.push_back(data_file + ":" + std::to_string(line));
  std::error_code error;
  const bool from_file = !data.lines.empty() && std::filesystem::is_regular_file(data_file, error);
  return camera_view_checks(
      model, params, data.data, labels,
      from_file ? images_of_rows(data_file, data.lines) : std::vector<std::string>());
}

}  // namespace kincal
