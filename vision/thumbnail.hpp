#pragma once
// A small picture of an image for the pages for people: the image read by OpenCV, scaled to
// at most `max_width` px wide (never enlarged), encoded as JPEG and returned as a data URI
// that an HTML page shows without the file ("data:image/jpeg;base64,...").

#include <string>
#include <vector>

#include "kincal/framework/analysis/image_views.hpp"

namespace kincal::vision {

/// The thumbnail of the image file at `path` as a data URI; "" when OpenCV cannot read it
/// (the page then draws the view on a blank frame).
std::string image_thumbnail(const std::string& path, int max_width = 320);

/// Gives each view of `views` that names its image (ImageView::image) the thumbnail of that
/// image, the name taken relative to `folder` unless absolute. Returns the names of the images
/// that could not be read (their views keep no thumbnail).
std::vector<std::string> add_thumbnails(std::vector<ImageViews>& views, const std::string& folder,
                                        int max_width = 320);

/// add_thumbnails, and what to tell the user when images named could not be read ("" when
/// all were, or none is named): "N image(s) named in the data not read from 'DIR' (first:
/// NAME); their views are drawn without them".
std::string draw_views_on_images(std::vector<ImageViews>& views, const std::string& folder);

/// `bytes` in base64 (RFC 4648, with padding).
std::string base64(const std::string& bytes);

}  // namespace kincal::vision
