#include "kincal/vision/intrinsics.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>

namespace kincal::vision {

IntrinsicsFit calibrate_intrinsics(const std::vector<Detection>& detections,
                                   const TargetSpec& target, int width, int height) {
  IntrinsicsFit fit;
  const CameraTarget points = target.camera_target();
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const Detection& d : detections) {
    if (d.status != DetectionStatus::kFound) continue;
    object.emplace_back();
    image.emplace_back();
    for (std::size_t k = 0; k < d.points.size(); ++k) {
      if (!std::isfinite(d.points[k].x())) continue;
      const Vector3d& p = points.points[k];
      object.back().emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
      image.back().emplace_back(static_cast<float>(d.points[k].x()),
                                static_cast<float>(d.points[k].y()));
    }
  }
  fit.views = static_cast<int>(object.size());
  if (fit.views < 3) {
    fit.reason = std::to_string(fit.views) +
                 " views with the target (OpenCV's calibration of "
                 "the intrinsics needs 3 or more)";
    return fit;
  }
  cv::Mat K, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    fit.rms_px = cv::calibrateCamera(object, image, cv::Size(width, height), K, distortion, rvecs,
                                     tvecs, cv::CALIB_FIX_K3);
  } catch (const cv::Exception& e) {
    fit.reason = std::string("OpenCV's calibrateCamera failed: ") + e.what();
    return fit;
  }
  fit.intrinsics.fx = K.at<double>(0, 0);
  fit.intrinsics.fy = K.at<double>(1, 1);
  fit.intrinsics.cx = K.at<double>(0, 2);
  fit.intrinsics.cy = K.at<double>(1, 2);
  // OpenCV's order: k1, k2, p1, p2, k3.
  fit.intrinsics.k1 = distortion.at<double>(0);
  fit.intrinsics.k2 = distortion.at<double>(1);
  fit.intrinsics.p1 = distortion.at<double>(2);
  fit.intrinsics.p2 = distortion.at<double>(3);
  fit.intrinsics.k3 = distortion.at<double>(4);
  fit.ok = std::isfinite(fit.rms_px) && fit.intrinsics.fx > 0 && fit.intrinsics.fy > 0;
  if (!fit.ok) fit.reason = "OpenCV's calibrateCamera gave no usable intrinsics";
  return fit;
}

}  // namespace kincal::vision
