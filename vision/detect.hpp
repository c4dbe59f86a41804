#pragma once
// `kincal detect` as one call: images in, a measurement table out, one row per image in which
// the target was found (its pose columns copied from the user's file, the camera's readings
// u, v per point, undetected points empty), with what became of every image; and, when asked,
// a starting model (the camera's intrinsics from OpenCV's calibration or the user's, both
// mounts from the closed-form hand-eye solution). Nothing is written or printed here: the
// command and Python write the texts returned.

#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kincal/framework/kinematics/measurement_model.hpp"
#include "kincal/models/camera_start.hpp"
#include "kincal/vision/intrinsics.hpp"

namespace kincal::vision {

/// The images and the poses the robot reported at each: a CSV file with a column `image` (the
/// image file, relative to the folder of the poses file or to `images_folder`) and the
/// configuration's columns as a measurement file names them (joint1_deg, flange.x_m, ...),
/// copied as written. Throws std::invalid_argument "<path>:<line>: ..." for a missing or
/// repeated `image` column, a row with the wrong number of fields, a value that is not a
/// number, an image named twice or missing.
struct ImagePoses {
  std::vector<std::string> images;  ///< as written in the file
  std::vector<std::string> paths;   ///< where to read them
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> values;  ///< per image, per column
  std::vector<int> lines;                        ///< per image, its line in the file
};
ImagePoses read_image_poses(const std::string& path, const std::string& images_folder = "");
/// The same from a stream; `source` names it in messages, images are relative to `folder`,
/// and their files are checked to exist only when `require_images` (the fuzzer reads names
/// of files that are not there).
ImagePoses parse_image_poses(std::istream& in, const std::string& source, const std::string& folder,
                             bool require_images);
/// Every image file (png, jpg, jpeg, bmp, tif, tiff, pgm, ppm) in `folder`, in natural order (2.png
/// before 10.png), without pose columns. Throws std::invalid_argument when there is none.
ImagePoses images_in_folder(const std::string& folder);

struct DetectRequest {
  ImagePoses images;
  TargetSpec target;
  std::string camera_name = "camera";
  DetectionOptions options;
  /// Called after each image, with how many are done; may be empty.
  std::function<void(int done)> on_image;
  /// Checked before each image: true stops the run with what was done (Ctrl-C).
  std::function<bool()> stop_requested;
};

struct ImageRecord {
  std::string image;  ///< as written in the poses file
  Detection detection;
};

struct DetectResult {
  std::vector<ImageRecord> records;  ///< the images looked at, in order
  int total = 0;                     ///< images asked for
  bool interrupted = false;          ///< stopped before the end (records holds those done)
  int width = 0, height = 0;         ///< the images' size (px), from the first one read
  int found() const;
  /// The measurement file: a header, then one row per image whose target was found.
  std::string csv(const DetectRequest& request) const;
  /// The table of what became of every image, for people.
  std::string text() const;
  /// The same as JSON: {"images": [{"image", "status", "points", "homography_rms_px",
  /// "reason"}], "found", "total", "interrupted", "width", "height"}.
  nlohmann::ordered_json json() const;
};

DetectResult detect_images(const DetectRequest& request);

/// What a starting model is made of.
struct StartRequest {
  CameraMounting mounting = CameraMounting::kEyeToHand;
  /// The mechanism whose configuration the pose columns give; empty: the flange-pose mechanism
  /// (models/flange_pose.hpp).
  std::shared_ptr<const Mechanism> mechanism;
  /// The user's intrinsics (fx, fy, cx, cy; no distortion); empty: OpenCV's calibration of
  /// the detections.
  std::optional<CameraIntrinsics> intrinsics;
};

struct StartResult {
  std::shared_ptr<MeasurementModel> model;  ///< nominal values: the starting values
  IntrinsicsFit intrinsics;                 ///< OpenCV's, when it was used
  CameraMountStart mounts;
  std::string model_text;  ///< the model file
  /// A few lines for people: the intrinsics' source, the hand-eye fit, each view's pose error.
  std::string text() const;
};

/// A starting model for `result` (its found images) under `request`. Throws
/// std::invalid_argument with the reason when the intrinsics or the mounts cannot be found
/// (too few views, the pose columns not the mechanism's).
StartResult start_model(const DetectRequest& request, const DetectResult& result,
                        const StartRequest& start);

/// What `kincal detect` writes and says, for the program and Python alike.
struct DetectOutputs {
  std::string csv;          ///< the measurement file; "" when no image has the target
  std::string model_text;   ///< the starting model's file; "" unless asked for and made
  std::string start_text;   ///< start_model's words, when made
  std::string start_error;  ///< why a starting model asked for was not made; "" otherwise
  /// The report: {"format": "kincal-detect", "version": 1} and DetectResult::json().
  nlohmann::ordered_json json;
};

/// The outputs of `result`: the table, the report and, with `start`, a starting model (not
/// from an interrupted run, whose images are only part of the set).
DetectOutputs detect_outputs(const DetectRequest& request, const DetectResult& result,
                             const std::optional<StartRequest>& start);

}  // namespace kincal::vision
