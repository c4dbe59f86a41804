// kincal export --format camera-info: a camera's intrinsics as ROS's sensor_msgs/CameraInfo
// YAML (camera_calibration_parsers' file), written by hand: a dozen fixed keys need no YAML
// library.

#include <cmath>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/models/camera.hpp"
#include "kincal/models/export_formats.hpp"

namespace kincal {

namespace {

std::string numbers(std::initializer_list<double> values) {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : ", ") + format_text("%.17g", v + 0.0);
  return "[" + text + "]";
}

}  // namespace

std::string export_camera_info(const MeasurementModel& model, const ExportSource& source) {
  const Camera* camera = nullptr;
  int index = -1, cameras = 0;
  for (std::size_t s = 0; s < model.sensors().size(); ++s)
    if (const auto* c = dynamic_cast<const Camera*>(model.sensors()[s].get())) {
      ++cameras;
      camera = c;
      index = static_cast<int>(s);
    }
  if (cameras != 1)
    throw ExportError("camera-info writes one camera, and the model has " +
                      std::to_string(cameras));
  const double width = camera->image_width(), height = camera->image_height();
  if (width != std::round(width) || height != std::round(height))
    throw ExportError("camera-info needs the image's size in whole pixels, and the model has " +
                      format_text("%g x %g", width, height));
  const VectorXd values = model.parameters().nominal_values().segment(
      model.sensor_parameter_offset(index), camera->num_parameters());
  const double* in = values.data() + Camera::kIntrinsicsIndex;
  const double fx = in[0], fy = in[1], cx = in[2], cy = in[3];
  const double k1 = in[4], k2 = in[5], k3 = in[6], p1 = in[7], p2 = in[8];
  std::string text = "# kincal export: camera '" + camera->name() + "' of " + source.model_file;
  if (!source.sha256.empty()) text += " (sha256 " + source.sha256 + ")";
  text +=
      "\n# ROS camera_info: pixels with the top-left pixel's centre at (0, 0), OpenCV's\n"
      "# pinhole and plumb_bob distortion (k1, k2, p1, p2, k3).\n";
  text += format_text("image_width: %d\nimage_height: %d\n", static_cast<int>(width),
                      static_cast<int>(height));
  text += "camera_name: " + camera->name() + "\n";
  text +=
      "camera_matrix:\n  rows: 3\n  cols: 3\n  data: " + numbers({fx, 0, cx, 0, fy, cy, 0, 0, 1}) +
      "\n";
  text += "distortion_model: plumb_bob\n";
  text +=
      "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: " + numbers({k1, k2, p1, p2, k3}) +
      "\n";
  text += "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: " +
          numbers({1, 0, 0, 0, 1, 0, 0, 0, 1}) + "\n";
  text += "projection_matrix:\n  rows: 3\n  cols: 4\n  data: " +
          numbers({fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0}) + "\n";
  return text;
}

}  // namespace kincal
