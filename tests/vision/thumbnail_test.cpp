// Thumbnails of images for the calibration page (vision/thumbnail.hpp).
#include "kincal/vision/thumbnail.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

namespace kincal::vision {
namespace {

TEST(Thumbnail, Base64IsRfc4648s) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00\xfe", 3)), "/wD+");
}

// base64's inverse, for the test only.
std::vector<unsigned char> decode(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> out;
  unsigned bits = 0, value = 0;
  for (char c : text) {
    if (c == '=') break;
    value = value << 6 | static_cast<unsigned>(alphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>(value >> bits & 0xff));
    }
  }
  return out;
}

TEST(Thumbnail, AnImageScaledToTheWidthAsAJpegDataUriAndNothingForWhatIsNotAnImage) {
  const auto folder =
      std::filesystem::temp_directory_path() / ("kincal-thumbnail-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar(20, 120, 220));
  ASSERT_TRUE(cv::imwrite((folder / "v.png").string(), image));
  const std::string uri = image_thumbnail((folder / "v.png").string(), 320);
  const std::string prefix = "data:image/jpeg;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  const cv::Mat back = cv::imdecode(decode(uri.substr(prefix.size())), cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.cols, 320);
  EXPECT_EQ(back.rows, 240);
  EXPECT_NEAR(back.at<cv::Vec3b>(100, 100)[2], 220, 4);

  ImageViews views;
  views.views.resize(3);
  views.views[0].image = "v.png";
  views.views[1].image = "missing.png";
  std::vector<ImageViews> all = {views};
  EXPECT_EQ(add_thumbnails(all, folder.string()), std::vector<std::string>{"missing.png"});
  EXPECT_EQ(all[0].views[0].thumbnail.rfind(prefix, 0), 0u);
  EXPECT_TRUE(all[0].views[1].thumbnail.empty());
  EXPECT_TRUE(all[0].views[2].thumbnail.empty());  // no image named
  EXPECT_NE(draw_views_on_images(all, folder.string()).find("1 image(s) named in the data"),
            std::string::npos);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace kincal::vision
