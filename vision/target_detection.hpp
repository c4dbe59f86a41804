#pragma once
// Finding a calibration target's points in an image, with OpenCV (Debian's libopencv-dev and,
// for ChArUco, libopencv-contrib-dev): the one place kincal reads images. OpenCV's headers
// stay in the .cpp files of this folder.
//
// Targets, as written on the command line (lengths with their unit):
//   chessboard:ROWSxCOLS:SPACING        inner corners, ROWS x COLS, SPACING apart
//   circle-grid:ROWSxCOLS:SPACING       a symmetric grid of dark dots on a light ground
//   modified-circle-grid:ROWSxCOLS:SPACING
//                                       the same with one larger dot, at the grid's origin,
//                                       which fixes its orientation (ROS-Industrial's target)
//   charuco:ROWSxCOLS:SQUARE:MARKER:DICTIONARY
//                                       a ChArUco board of ROWS x COLS squares, its inner
//                                       corners (ROWS - 1) x (COLS - 1); DICTIONARY an ArUco
//                                       dictionary's name, e.g. DICT_6X6_250
// Points are numbered row by row as CameraTarget::grid numbers them: point (r, c) at
// (c, r) x spacing in the target's frame, r counting rows of COLS points. A chessboard's
// corners come in OpenCV's order, which for a board that looks the same turned by 180 degrees
// may differ between images (print one with an odd and an even count); a modified circle
// grid's start at its large dot, x along the dot's row, z out of the printed face; a ChArUco
// board's are numbered by its markers, and each detected corner is a point (the others are
// missing readings).

#include <string>
#include <vector>

#include "kincal/models/camera.hpp"

namespace kincal::vision {

enum class TargetKind { kChessboard, kCircleGrid, kModifiedCircleGrid, kCharuco };

struct TargetSpec {
  TargetKind kind = TargetKind::kChessboard;
  int rows = 0, columns = 0;  ///< of points (a ChArUco board: of squares)
  double spacing = 0;         ///< mm: between points (a ChArUco board: a square's side)
  double marker = 0;          ///< mm: a ChArUco marker's side
  std::string dictionary;     ///< a ChArUco board's ArUco dictionary, e.g. "DICT_6X6_250"
  std::string text;           ///< as written

  /// Parses the forms above. Throws std::invalid_argument with what was expected.
  static TargetSpec parse(const std::string& text);
  /// The target's points as the camera model takes them (mm).
  CameraTarget camera_target() const;
  int num_points() const;
};

/// How a detection came out.
enum class DetectionStatus {
  kFound,       ///< the target's points, passed the gate
  kRejected,    ///< found, but the gate refused them (reason says why)
  kNotFound,    ///< the target is not in the image, or not whole
  kUnreadable,  ///< the file is not an image OpenCV reads
};
const char* to_string(DetectionStatus status);

struct DetectionOptions {
  /// The gate: the RMS distance (px) between the detected points and the homography fitted to
  /// them (the plane's image under a lens without distortion). A wrongly ordered or partly
  /// wrong detection shows as a large residual; a strongly distorting lens needs a larger
  /// gate.
  double max_homography_rms_px = 2.0;
  /// Fewer points than this (ChArUco boards, seen in part) is no detection: a view's pose
  /// needs several.
  int min_points = 6;
};

struct Detection {
  DetectionStatus status = DetectionStatus::kNotFound;
  std::string reason;         ///< why not kFound, in words
  int width = 0, height = 0;  ///< the image's size (px), when read
  /// Per target point, (u, v) in px (the top-left pixel's centre is 0, 0), NaN when not
  /// detected.
  std::vector<Eigen::Vector2d> points;
  int found = 0;                 ///< points detected
  double homography_rms_px = 0;  ///< the gate's measure
};

/// Finds `target` in the image file `path`.
Detection detect_target(const std::string& path, const TargetSpec& target,
                        const DetectionOptions& options = {});

/// The names of the ArUco dictionaries the ChArUco finder knows.
std::vector<std::string> aruco_dictionary_names();

}  // namespace kincal::vision
