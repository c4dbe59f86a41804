// The reprojection error per view (framework/analysis/image_views.hpp) and its section of the
// calibration page (framework/report/sections.hpp: image_views_html).
#include "kincal/framework/analysis/image_views.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "kincal/framework/report/sections.hpp"

namespace kincal {
namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

ImageViews two_views() {
  ImageViews views;
  views.sensor = "cam<1>";
  views.width = 640;
  views.height = 480;
  ImageView a;
  a.label = "D.csv:2";
  a.image = "a&b.png";
  a.measured = {{100, 100}, {200, 100}};
  a.predicted = {{103, 104}, {200, 100}};  // 5 px and 0 px
  ImageView b;
  b.label = "D.csv:3";
  b.measured = {{300, 300}};
  b.predicted = {{301, 300}};  // 1 px
  views.views = {a, b};
  summarise_image_views(views);
  return views;
}

TEST(ImageViews, SummarisesEachViewAndAllPointsAsDistancesInPixels) {
  const ImageViews views = two_views();
  EXPECT_DOUBLE_EQ(views.views[0].mean_px, 2.5);
  EXPECT_DOUBLE_EQ(views.views[0].rms_px, std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(views.views[0].max_px, 5);
  EXPECT_DOUBLE_EQ(views.views[1].rms_px, 1);
  EXPECT_EQ(views.points, 3);
  EXPECT_DOUBLE_EQ(views.mean_px, 2);
  EXPECT_DOUBLE_EQ(views.rms_px, std::sqrt(26.0 / 3));
  EXPECT_DOUBLE_EQ(views.max_px, 5);

  const std::string text = image_views_text(views, 1);
  EXPECT_NE(text.find("3 points in 2 views"), std::string::npos) << text;
  EXPECT_NE(text.find("the 1 views with the largest RMS"), std::string::npos) << text;
  EXPECT_NE(text.find("D.csv:2"), std::string::npos) << text;
  EXPECT_EQ(text.find("D.csv:3"), std::string::npos) << text;

  const auto json = image_views_json(views);
  EXPECT_EQ(json["points"], 3);
  ASSERT_EQ(json["views"].size(), 2u);
  EXPECT_EQ(json["views"][0]["image"], "a&b.png");
  EXPECT_DOUBLE_EQ(json["views"][1]["max_px"].get<double>(), 1);

  ImageViews empty;
  summarise_image_views(empty);
  EXPECT_TRUE(std::isnan(empty.rms_px));
  EXPECT_TRUE(image_views_json(empty)["rms_px"].is_null());
}

TEST(ImageViews, ThePageDrawsEveryPointWithItsResidualMagnifiedAndEscapesNames) {
  ImageViews views = two_views();
  std::string html = report::image_views_html(views);
  EXPECT_EQ(count(html, "class=\"seen\""), 3);
  EXPECT_EQ(count(html, "class=\"residual\""), 3);
  EXPECT_EQ(count(html, "class=\"blank\""), 2);  // no thumbnails
  EXPECT_EQ(html.find("cam<1>"), std::string::npos);
  EXPECT_NE(html.find("cam&lt;1&gt;"), std::string::npos);
  EXPECT_NE(html.find("a&amp;b.png"), std::string::npos);
  // The largest residual (5 px) drawn about 12 % of 640 px long: 76.8 / 5 rounds down to 10.
  EXPECT_NE(html.find("magnified 10 times"), std::string::npos) << html.substr(0, 800);
  EXPECT_NE(html.find("x2=\"130.00\" y2=\"140.00\""), std::string::npos);  // 100 + 10 * (3, 4)
  views.views[1].thumbnail = "data:image/jpeg;base64,AAAA";
  html = report::image_views_html(views);
  EXPECT_EQ(count(html, "<image "), 1);
  EXPECT_NE(html.find("on the image"), std::string::npos);
}

}  // namespace
}  // namespace kincal
