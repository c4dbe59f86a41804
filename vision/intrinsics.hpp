#pragma once
// The camera's intrinsics from detected planar targets alone, by OpenCV's calibrateCamera
// (Zhang's method, then the reprojection error minimised): the starting intrinsics of a
// camera calibration when the user gives none. kincal's calibration fits them again with
// the rest.

#include <string>
#include <vector>

#include "kincal/vision/target_detection.hpp"

namespace kincal::vision {

struct IntrinsicsFit {
  bool ok = false;
  std::string reason;  ///< why not, when !ok
  CameraIntrinsics intrinsics;
  double rms_px = 0;  ///< OpenCV's reprojection error
  int views = 0;
};

/// From the detections whose status is kFound (all of one image size, `width` x `height`),
/// distortion k1, k2, p1, p2 (k3 fixed at 0, as kincal's default mask). Needs 3 views.
IntrinsicsFit calibrate_intrinsics(const std::vector<Detection>& detections,
                                   const TargetSpec& target, int width, int height);

}  // namespace kincal::vision
