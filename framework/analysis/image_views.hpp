#pragma once
// Reprojection error in a camera user's terms: per view (one configuration seen by a sensor
// that reads pixels, e.g. a camera) its points as measured and as the calibrated model
// predicts them, and the distance between the two in px, summed up per view (mean, RMS, max)
// and over all views. The sensor-specific part (which readings are a point's u and v) is the
// sensor's: models/camera_views.hpp fills these; the report pages draw them.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kincal/framework/base/types.hpp"

namespace kincal {

/// One view: the points measured in one configuration.
struct ImageView {
  std::string label;  ///< the data row, e.g. "D.csv:12"
  std::string image;  ///< the image file the view came from ("" when not known)
  std::vector<Eigen::Vector2d> measured, predicted;  ///< px, per point measured in this view
  /// |predicted - measured| per point: mean, RMS and max (px); NaN without a point.
  double mean_px = 0, rms_px = 0, max_px = 0;
  /// A small picture of the image as a data URI ("data:image/jpeg;base64,..."), for the page
  /// for people; "" when there is none (made by the caller that can read images).
  std::string thumbnail;
};

/// A sensor's views and their summary.
struct ImageViews {
  std::string sensor;
  double width = 0, height = 0;  ///< the image's size (px)
  std::vector<ImageView> views;  ///< in data order
  /// Over every point of every view (px); NaN without a point.
  double mean_px = 0, rms_px = 0, max_px = 0;
  int points = 0;  ///< points measured in all
};

/// Fills the per-view and overall figures of `views` from their points.
void summarise_image_views(ImageViews& views);

/// The figures in words: the overall mean, RMS and max, then the `worst` views with the
/// largest RMS (all of them when there are no more), each with its label and image.
std::string image_views_text(const ImageViews& views, int worst = 5);

/// The same as JSON, every view: {"sensor", "width", "height", "points", "mean_px",
/// "rms_px", "max_px", "views": [{"label", "image", "points", "mean_px", "rms_px",
/// "max_px"}]} (no points, no thumbnail).
nlohmann::ordered_json image_views_json(const ImageViews& views);

}  // namespace kincal
