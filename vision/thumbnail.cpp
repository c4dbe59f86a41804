#include "kincal/vision/thumbnail.hpp"

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace kincal::vision {

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0u);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += two ? kAlphabet[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

std::string image_thumbnail(const std::string& path, int max_width) {
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_COLOR);
    if (image.empty() || max_width < 1) return "";
    if (image.cols > max_width) {
      cv::Mat small;
      const double f = static_cast<double>(max_width) / image.cols;
      cv::resize(image, small, cv::Size(), f, f, cv::INTER_AREA);
      image = small;
    }
    std::vector<unsigned char> jpeg;
    if (!cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 75})) return "";
    return "data:image/jpeg;base64," + base64(std::string(jpeg.begin(), jpeg.end()));
  } catch (const cv::Exception&) {
    return "";
  }
}

std::vector<std::string> add_thumbnails(std::vector<ImageViews>& views, const std::string& folder,
                                        int max_width) {
  std::vector<std::string> unread;
  for (ImageViews& sensor : views)
    for (ImageView& view : sensor.views) {
      if (view.image.empty()) continue;
      const std::filesystem::path name(view.image);
      const std::string path = name.is_absolute() || folder.empty()
                                   ? name.string()
                                   : (std::filesystem::path(folder) / name).string();
      view.thumbnail = image_thumbnail(path, max_width);
      if (view.thumbnail.empty()) unread.push_back(view.image);
    }
  return unread;
}

std::string draw_views_on_images(std::vector<ImageViews>& views, const std::string& folder) {
  const std::vector<std::string> unread = add_thumbnails(views, folder);
  if (unread.empty()) return "";
  return std::to_string(unread.size()) + " image(s) named in the data not read from '" +
         (folder.empty() ? std::string(".") : folder) + "' (first: " + unread.front() +
         "); their views are drawn without them";
}

}  // namespace kincal::vision
