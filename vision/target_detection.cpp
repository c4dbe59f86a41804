#include "kincal/vision/target_detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "kincal/framework/base/format_text.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/kinematics/units.hpp"

namespace kincal::vision {

namespace {

struct DictionaryName {
  const char* name;
  cv::aruco::PREDEFINED_DICTIONARY_NAME id;
};
const DictionaryName kDictionaries[] = {
    {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
    {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
    {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
    {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
    {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
    {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
    {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
    {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
    {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
    {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
    {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
    {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
    {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
    {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
    {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
    {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
    {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
};

// "25.4mm", "0.0254m": a length in mm.
double parse_length(const std::string& text, const std::string& what, const std::string& whole) {
  std::size_t end = 0;
  double value = 0;
  try {
    value = std::stod(text, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  const std::string unit_name = end ? text.substr(end) : "";
  Unit unit;
  if (!end || unit_name.empty() || !UnitRegistry::global().find(unit_name, &unit) ||
      unit.base != kMillimetre || !(value > 0) || !std::isfinite(value))
    throw std::invalid_argument("target '" + message_excerpt(whole) + "': " + what + " '" +
                                message_excerpt(text) +
                                "': expected a positive length with its unit, e.g. 25.4mm");
  return value * unit.factor;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> fields;
  std::string::size_type start = 0;
  while (true) {
    const auto end = text.find(separator, start);
    fields.push_back(text.substr(start, end - start));
    if (end == std::string::npos) return fields;
    start = end + 1;
  }
}

cv::Ptr<cv::aruco::Dictionary> dictionary(const std::string& name) {
  for (const auto& d : kDictionaries)
    if (name == d.name) return cv::aruco::getPredefinedDictionary(d.id);
  throw std::invalid_argument("unknown ArUco dictionary '" + message_excerpt(name) + "'");
}

// The blob detector for dark dots of a grid of `count` dots in a width x height image.
cv::Ptr<cv::SimpleBlobDetector> dot_detector(int width, int height, int count) {
  cv::SimpleBlobDetector::Params params;
  params.minThreshold = 20;
  params.maxThreshold = 220;
  params.thresholdStep = 10;
  params.filterByColor = true;
  params.blobColor = 0;
  params.filterByArea = true;
  params.minArea = 25;
  params.maxArea = std::max(5000.0f, 0.5f * static_cast<float>(width) * static_cast<float>(height) /
                                         static_cast<float>(count));
  params.filterByCircularity = false;
  params.filterByInertia = false;
  params.filterByConvexity = false;
  return cv::SimpleBlobDetector::create(params);
}

// A modified circle grid's points reordered from OpenCV's grid order so that point 0 is the
// large dot and x runs along its row, the target's z towards the camera; false with a reason
// when the large dot is not found at a corner.
bool order_from_large_dot(const cv::Mat& gray, const TargetSpec& target,
                          const cv::Ptr<cv::SimpleBlobDetector>& detector,
                          std::vector<cv::Point2f>& centres, std::string& reason) {
  std::vector<cv::KeyPoint> blobs;
  detector->detect(gray, blobs);
  if (blobs.empty()) {
    reason = "no dots";
    return false;
  }
  // The size of the dot at each grid centre (other blobs in the image are not the target's).
  const double spacing_px = cv::norm(centres[1] - centres[0]);
  std::vector<float> sizes(centres.size(), 0.0f);
  for (std::size_t k = 0; k < centres.size(); ++k)
    for (const auto& b : blobs)
      if (cv::norm(b.pt - centres[k]) < 0.3 * spacing_px) sizes[k] = std::max(sizes[k], b.size);
  const int nearest =
      static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  std::vector<float> sorted = sizes;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const float median = sorted[sorted.size() / 2];
  if (!(sizes[static_cast<std::size_t>(nearest)] > 1.3f * median)) {
    reason = "no dot larger than the others (a modified circle grid has one)";
    return false;
  }
  const int rows = target.rows, cols = target.columns;
  const int i0 = nearest / cols, j0 = nearest % cols;
  if ((i0 != 0 && i0 != rows - 1) || (j0 != 0 && j0 != cols - 1)) {
    reason = "the large dot is not at a corner of the grid";
    return false;
  }
  const int di = i0 == 0 ? 1 : -1, dj = j0 == 0 ? 1 : -1;
  // (r, c) of the target from OpenCV's (i, j): x along j, or (a square grid) along i.
  auto reorder = [&](bool x_along_j) {
    std::vector<cv::Point2f> out(centres.size());
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const int i = x_along_j ? i0 + di * r : i0 + di * c;
        const int j = x_along_j ? j0 + dj * c : j0 + dj * r;
        out[static_cast<std::size_t>(r * cols + c)] =
            centres[static_cast<std::size_t>(i * cols + j)];
      }
    return out;
  };
  // Seen from the front, x to the right and y up the image: x cross y < 0 in image
  // coordinates (v grows downwards).
  auto facing = [&](const std::vector<cv::Point2f>& p) {
    const cv::Point2f x = p[1] - p[0];
    const cv::Point2f y = p[static_cast<std::size_t>(cols)] - p[0];
    return x.x * y.y - x.y * y.x < 0;
  };
  std::vector<cv::Point2f> ordered = reorder(true);
  if (!facing(ordered) && rows == cols) ordered = reorder(false);
  if (!facing(ordered)) {
    reason = "the grid appears mirrored (seen from behind, or rows and columns swapped)";
    return false;
  }
  centres = ordered;
  return true;
}

double homography_rms(const std::vector<cv::Point2f>& plane,
                      const std::vector<cv::Point2f>& image) {
  const cv::Mat H = cv::findHomography(plane, image, 0);
  if (H.empty()) return std::numeric_limits<double>::infinity();
  std::vector<cv::Point2f> mapped;
  cv::perspectiveTransform(plane, mapped, H);
  double sum = 0;
  for (std::size_t k = 0; k < image.size(); ++k) {
    const cv::Point2f d = mapped[k] - image[k];
    sum += d.dot(d);
  }
  return std::sqrt(sum / static_cast<double>(image.size()));
}

}  // namespace

std::vector<std::string> aruco_dictionary_names() {
  std::vector<std::string> names;
  for (const auto& d : kDictionaries) names.emplace_back(d.name);
  return names;
}

const char* to_string(DetectionStatus status) {
  switch (status) {
    case DetectionStatus::kFound:
      return "found";
    case DetectionStatus::kRejected:
      return "rejected";
    case DetectionStatus::kNotFound:
      return "not found";
    case DetectionStatus::kUnreadable:
      return "unreadable";
  }
  return "?";
}

TargetSpec TargetSpec::parse(const std::string& text) {
  const std::vector<std::string> f = split(text, ':');
  TargetSpec spec;
  spec.text = text;
  const std::string forms =
      "chessboard:ROWSxCOLS:SPACING, circle-grid:ROWSxCOLS:SPACING, "
      "modified-circle-grid:ROWSxCOLS:SPACING or charuco:ROWSxCOLS:SQUARE:MARKER:DICTIONARY";
  const std::string& kind = f[0];
  std::size_t fields = 3;
  if (kind == "chessboard") {
    spec.kind = TargetKind::kChessboard;
  } else if (kind == "circle-grid") {
    spec.kind = TargetKind::kCircleGrid;
  } else if (kind == "modified-circle-grid") {
    spec.kind = TargetKind::kModifiedCircleGrid;
  } else if (kind == "charuco") {
    spec.kind = TargetKind::kCharuco;
    fields = 5;
  } else {
    throw std::invalid_argument("target '" + message_excerpt(text) + "': unknown kind '" +
                                message_excerpt(kind) + "'; expected " + forms);
  }
  if (f.size() != fields)
    throw std::invalid_argument("target '" + message_excerpt(text) + "': expected " + forms);
  const auto x = f[1].find('x');
  try {
    std::size_t end = 0;
    spec.rows = std::stoi(f[1].substr(0, x), &end);
    if (end != x) throw std::invalid_argument("");
    spec.columns = std::stoi(f[1].substr(x + 1), &end);
    if (end != f[1].size() - x - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    spec.rows = 0;
  }
  const int least = spec.kind == TargetKind::kCharuco ? 3 : 2;
  if (x == std::string::npos || spec.rows < least || spec.columns < least || spec.rows > 1000 ||
      spec.columns > 1000)
    throw std::invalid_argument("target '" + message_excerpt(text) + "': '" +
                                message_excerpt(f[1]) + "': expected ROWSxCOLS, " +
                                "each at least " + std::to_string(least) +
                                (spec.kind == TargetKind::kCharuco ? " squares" : " points"));
  spec.spacing =
      parse_length(f[2], spec.kind == TargetKind::kCharuco ? "the square" : "the spacing", text);
  if (spec.kind == TargetKind::kCharuco) {
    spec.marker = parse_length(f[3], "the marker", text);
    if (!(spec.marker < spec.spacing))
      throw std::invalid_argument("target '" + message_excerpt(text) + "': the marker (" +
                                  message_excerpt(f[3]) + ") must be smaller than the square (" +
                                  message_excerpt(f[2]) + ")");
    spec.dictionary = f[4];
    const auto names = aruco_dictionary_names();
    if (std::find(names.begin(), names.end(), spec.dictionary) == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw std::invalid_argument("target '" + message_excerpt(text) +
                                  "': unknown ArUco dictionary '" +
                                  message_excerpt(spec.dictionary) + "'; expected one of " + list);
    }
  }
  return spec;
}

CameraTarget TargetSpec::camera_target() const {
  if (kind == TargetKind::kCharuco) return CameraTarget::grid(rows - 1, columns - 1, spacing);
  return CameraTarget::grid(rows, columns, spacing);
}

int TargetSpec::num_points() const {
  return kind == TargetKind::kCharuco ? (rows - 1) * (columns - 1) : rows * columns;
}

Detection detect_target(const std::string& path, const TargetSpec& target,
                        const DetectionOptions& options) {
  Detection detection;
  const int n = target.num_points();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  detection.points.assign(static_cast<std::size_t>(n), Eigen::Vector2d(nan, nan));
  cv::Mat gray;
  try {
    gray = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    gray.release();
  }
  if (gray.empty()) {
    detection.status = DetectionStatus::kUnreadable;
    detection.reason = "not an image OpenCV can read";
    return detection;
  }
  detection.width = gray.cols;
  detection.height = gray.rows;

  // Detected points with their index among the target's.
  std::vector<cv::Point2f> pixels;
  std::vector<int> indices;
  try {
    const cv::Size pattern(target.columns, target.rows);
    switch (target.kind) {
      case TargetKind::kChessboard: {
        if (!cv::findChessboardCorners(
                gray, pattern, pixels,
                cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
          detection.reason = "no " + std::to_string(target.rows) + " x " +
                             std::to_string(target.columns) + " chessboard (inner corners)";
          return detection;
        }
        // The refinement's window: a quarter of the smallest distance between corners.
        double nearest = std::numeric_limits<double>::infinity();
        for (int r = 0; r < target.rows; ++r)
          for (int c = 0; c + 1 < target.columns; ++c)
            nearest = std::min<double>(
                nearest, cv::norm(pixels[static_cast<std::size_t>(r * target.columns + c + 1)] -
                                  pixels[static_cast<std::size_t>(r * target.columns + c)]));
        const int half = std::clamp(static_cast<int>(nearest / 4), 2, 11);
        cv::cornerSubPix(
            gray, pixels, cv::Size(half, half), cv::Size(-1, -1),
            cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
        for (int k = 0; k < n; ++k) indices.push_back(k);
        break;
      }
      case TargetKind::kCircleGrid:
      case TargetKind::kModifiedCircleGrid: {
        const auto detector = dot_detector(gray.cols, gray.rows, n);
        if (!cv::findCirclesGrid(gray, pattern, pixels, cv::CALIB_CB_SYMMETRIC_GRID, detector)) {
          detection.reason = "no " + std::to_string(target.rows) + " x " +
                             std::to_string(target.columns) + " grid of dark dots";
          return detection;
        }
        if (target.kind == TargetKind::kModifiedCircleGrid &&
            !order_from_large_dot(gray, target, detector, pixels, detection.reason)) {
          detection.status = DetectionStatus::kRejected;
          return detection;
        }
        for (int k = 0; k < n; ++k) indices.push_back(k);
        break;
      }
      case TargetKind::kCharuco: {
        const auto dict = dictionary(target.dictionary);
        const auto board = cv::aruco::CharucoBoard::create(target.columns, target.rows,
                                                           static_cast<float>(target.spacing),
                                                           static_cast<float>(target.marker), dict);
        std::vector<std::vector<cv::Point2f>> markers;
        std::vector<int> marker_ids;
        cv::aruco::detectMarkers(gray, dict, markers, marker_ids);
        if (marker_ids.empty()) {
          detection.reason = "no " + target.dictionary + " markers";
          return detection;
        }
        std::vector<cv::Point2f> corners;
        std::vector<int> ids;
        cv::aruco::interpolateCornersCharuco(markers, marker_ids, gray, board, corners, ids);
        // A corner's index among the target's points from its position on OpenCV's board.
        for (std::size_t k = 0; k < ids.size(); ++k) {
          const cv::Point3f p = board->chessboardCorners[static_cast<std::size_t>(ids[k])];
          const int c = static_cast<int>(std::lround(p.x / target.spacing)) - 1;
          const int r = static_cast<int>(std::lround(p.y / target.spacing)) - 1;
          if (r < 0 || c < 0 || r >= target.rows - 1 || c >= target.columns - 1) continue;
          indices.push_back(r * (target.columns - 1) + c);
          pixels.push_back(corners[k]);
        }
        break;
      }
    }
  } catch (const cv::Exception& e) {
    detection.reason = std::string("OpenCV failed: ") + e.what();
    detection.status = DetectionStatus::kNotFound;
    return detection;
  }
  detection.found = static_cast<int>(pixels.size());
  if (detection.found < std::max(4, options.min_points)) {
    detection.status = DetectionStatus::kNotFound;
    detection.reason = std::to_string(detection.found) + " of the target's " + std::to_string(n) +
                       " points (at least " + std::to_string(std::max(4, options.min_points)) +
                       " needed)";
    return detection;
  }
  const CameraTarget points = target.camera_target();
  std::vector<cv::Point2f> plane;
  for (int index : indices) {
    const Vector3d& p = points.points[static_cast<std::size_t>(index)];
    plane.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  detection.homography_rms_px = homography_rms(plane, pixels);
  for (std::size_t k = 0; k < pixels.size(); ++k)
    detection.points[static_cast<std::size_t>(indices[k])] =
        Eigen::Vector2d(pixels[k].x, pixels[k].y);
  if (!(detection.homography_rms_px <= options.max_homography_rms_px)) {
    detection.status = DetectionStatus::kRejected;
    detection.reason = format_text(
        "the points are %.2f px (RMS) from a plane's image, beyond the "
        "gate of %.2f px",
        detection.homography_rms_px, options.max_homography_rms_px);
    return detection;
  }
  detection.status = DetectionStatus::kFound;
  return detection;
}

}  // namespace kincal::vision
