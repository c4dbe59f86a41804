// Finding targets in images (vision/target_detection.hpp, vision/detect.hpp) on images drawn
// here with a known geometry: a chessboard and a circle grid with one large dot rendered
// through a known homography, so that every point's true pixel is known; and the ways an image
// fails (unreadable, no target, a gate it does not pass), each with its reason.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "kincal/vision/detect.hpp"

namespace kincal::vision {
namespace {

namespace fs = std::filesystem;

// A folder of its own per test, removed at the end.
class TempFolder {
 public:
  TempFolder() {
    path_ = fs::temp_directory_path() /
            ("kincal-vision-" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// The homography from the target's plane (mm) to the image (px) of a board seen a little
// obliquely.
cv::Mat view(double scale, double shift_u, double shift_v) {
  cv::Mat H = (cv::Mat_<double>(3, 3) << scale, 0.08 * scale, shift_u, -0.05 * scale, scale * 0.95,
               shift_v, 2e-4, 1e-4, 1);
  return H;
}

cv::Point2d apply(const cv::Mat& H, double x, double y) {
  const cv::Mat p = H * (cv::Mat_<double>(3, 1) << x, y, 1);
  return {p.at<double>(0) / p.at<double>(2), p.at<double>(1) / p.at<double>(2)};
}

// Polygons given in the target's plane (mm) filled black on a white 640 x 480 image through
// H, drawn 8x supersampled and then reduced (anti-aliased edges, as a camera sees them).
cv::Mat draw(const std::vector<std::vector<cv::Point2d>>& polygons, const cv::Mat& H) {
  constexpr int kSuper = 8;
  cv::Mat big(480 * kSuper, 640 * kSuper, CV_8U, cv::Scalar(255));
  const cv::Mat S = (cv::Mat_<double>(3, 3) << kSuper, 0, (kSuper - 1) / 2.0, 0, kSuper,
                     (kSuper - 1) / 2.0, 0, 0, 1);
  const cv::Mat HS = S * H;
  for (const auto& polygon : polygons) {
    std::vector<cv::Point> pixels;
    for (const cv::Point2d& q : polygon) {
      const cv::Point2d p = apply(HS, q.x, q.y);
      pixels.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    }
    cv::fillConvexPoly(big, pixels, cv::Scalar(0), cv::LINE_8);
  }
  cv::Mat small;
  cv::resize(big, small, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
  return small;
}

// A chessboard of (rows + 1) x (columns + 1) squares of `square` mm, its inner corner (0, 0)
// at the plane's origin.
cv::Mat chessboard_image(int rows, int columns, double square, const cv::Mat& H) {
  std::vector<std::vector<cv::Point2d>> squares;
  for (int r = -1; r < rows; ++r)
    for (int c = -1; c < columns; ++c)
      if ((r + c) % 2 == 0)
        squares.push_back({{c * square, r * square},
                           {(c + 1) * square, r * square},
                           {(c + 1) * square, (r + 1) * square},
                           {c * square, (r + 1) * square}});
  return draw(squares, H);
}

// Dots a quarter of the spacing in radius at the grid's points, the one at (0, 0) twice as
// large.
cv::Mat circle_grid_image(int rows, int columns, double spacing, const cv::Mat& H) {
  std::vector<std::vector<cv::Point2d>> dots;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      const double radius = (r == 0 && c == 0 ? 0.5 : 0.25) * spacing;
      dots.emplace_back();
      for (int k = 0; k < 64; ++k) {
        const double a = 2 * M_PI * k / 64;
        dots.back().emplace_back(c * spacing + radius * std::cos(a),
                                 r * spacing + radius * std::sin(a));
      }
    }
  return draw(dots, H);
}

TEST(Detect, FindsAChessboardsCornersWhereTheyWereDrawn) {
  TempFolder folder;
  const cv::Mat H = view(5, 140, 110);
  ASSERT_TRUE(cv::imwrite(folder.file("board.png"), chessboard_image(5, 7, 10, H)));
  const TargetSpec target = TargetSpec::parse("chessboard:5x7:10mm");
  const Detection d = detect_target(folder.file("board.png"), target);
  ASSERT_EQ(d.status, DetectionStatus::kFound) << d.reason;
  EXPECT_EQ(d.found, 35);
  EXPECT_EQ(d.width, 640);
  EXPECT_LT(d.homography_rms_px, 0.2);
  // OpenCV may start from either end of a board that looks the same turned by 180 degrees:
  // compare with the drawn corners in whichever order fits.
  double direct = 0, turned = 0;
  for (int k = 0; k < 35; ++k) {
    const cv::Point2d truth = apply(H, (k % 7) * 10.0, (k / 7) * 10.0);
    const Eigen::Vector2d t(truth.x, truth.y);
    direct = std::max(direct, (d.points[static_cast<std::size_t>(k)] - t).norm());
    turned = std::max(turned, (d.points[static_cast<std::size_t>(34 - k)] - t).norm());
  }
  EXPECT_LT(std::min(direct, turned), 0.15) << "direct " << direct << ", turned " << turned;
}

TEST(Detect, OrdersAModifiedCircleGridFromItsLargeDot) {
  TempFolder folder;
  const cv::Mat H = view(6, 170, 100);
  ASSERT_TRUE(cv::imwrite(folder.file("grid.png"), circle_grid_image(6, 6, 10, H)));
  const Detection d =
      detect_target(folder.file("grid.png"), TargetSpec::parse("modified-circle-grid:6x6:10mm"));
  ASSERT_EQ(d.status, DetectionStatus::kFound) << d.reason;
  // Drawn with the plane's y down the image, the grid is seen from the front with the large
  // dot's neighbours to its right and below it; x along the row, z towards the camera makes
  // y point up the page, so x must run down the drawing (its y) and y along its x: point
  // (r, c) is the drawing's (x, y) = (r, c) x spacing.
  double worst = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) {
      const cv::Point2d t = apply(H, r * 10.0, c * 10.0);
      worst = std::max(
          worst,
          (d.points[static_cast<std::size_t>(r * 6 + c)] - Eigen::Vector2d(t.x, t.y)).norm());
    }
  EXPECT_LT(worst, 0.3);
  const cv::Point2d origin = apply(H, 0, 0);
  EXPECT_LT((d.points[0] - Eigen::Vector2d(origin.x, origin.y)).norm(), 0.3);
}

TEST(Detect, SaysWhyAnImageGaveNoPoints) {
  TempFolder folder;
  { std::ofstream(folder.file("text.png")) << "not an image"; }
  const TargetSpec target = TargetSpec::parse("chessboard:5x7:10mm");
  Detection d = detect_target(folder.file("text.png"), target);
  EXPECT_EQ(d.status, DetectionStatus::kUnreadable);
  EXPECT_NE(d.reason.find("not an image"), std::string::npos);

  ASSERT_TRUE(cv::imwrite(folder.file("blank.png"), cv::Mat(480, 640, CV_8U, cv::Scalar(200))));
  d = detect_target(folder.file("blank.png"), target);
  EXPECT_EQ(d.status, DetectionStatus::kNotFound);
  EXPECT_NE(d.reason.find("no 5 x 7 chessboard"), std::string::npos) << d.reason;

  // A board of the wrong size is not found as the one asked for.
  ASSERT_TRUE(cv::imwrite(folder.file("board.png"), chessboard_image(5, 7, 10, view(5, 140, 110))));
  d = detect_target(folder.file("board.png"), TargetSpec::parse("chessboard:6x8:10mm"));
  EXPECT_EQ(d.status, DetectionStatus::kNotFound);

  // A gate tighter than the corners' own residual rejects the detection, with the figures.
  DetectionOptions strict;
  strict.max_homography_rms_px = 1e-6;
  d = detect_target(folder.file("board.png"), target, strict);
  EXPECT_EQ(d.status, DetectionStatus::kRejected);
  EXPECT_NE(d.reason.find("beyond the gate"), std::string::npos) << d.reason;
}

TEST(Detect, TargetsAreParsedWithTheirUnitsOrRefusedInOneLine) {
  TargetSpec t = TargetSpec::parse("charuco:7x5:36.195mm:0.018256m:DICT_6X6_250");
  EXPECT_EQ(t.kind, TargetKind::kCharuco);
  EXPECT_EQ(t.num_points(), 24);
  EXPECT_DOUBLE_EQ(t.marker, 18.256);
  t = TargetSpec::parse("circle-grid:4x11:0.0254m");
  EXPECT_EQ(t.num_points(), 44);
  EXPECT_DOUBLE_EQ(t.spacing, 25.4);
  for (const char* bad :
       {"chessboard:5x7", "chessboard:5x7:10", "chessboard:1x7:10mm", "chessboard:5x7:10deg",
        "hexagon:5x7:10mm", "charuco:7x5:10mm:12mm:DICT_6X6_250", "charuco:7x5:36mm:18mm:DICT_9X9"})
    EXPECT_THROW(TargetSpec::parse(bad), std::invalid_argument) << bad;
}

TEST(Detect, WritesOneRowPerImageWithTheTargetAndTheirPoseColumns) {
  TempFolder folder;
  ASSERT_TRUE(cv::imwrite(folder.file("a.png"), chessboard_image(5, 7, 10, view(5, 140, 110))));
  ASSERT_TRUE(cv::imwrite(folder.file("b.png"), cv::Mat(480, 640, CV_8U, cv::Scalar(200))));
  {
    std::ofstream poses(folder.file("poses.csv"));
    poses << "image,joint1_deg\na.png,10\nb.png,20\n";
  }
  DetectRequest request;
  request.images = read_image_poses(folder.file("poses.csv"));
  request.target = TargetSpec::parse("chessboard:5x7:10mm");
  const DetectResult result = detect_images(request);
  EXPECT_EQ(result.found(), 1);
  const std::string csv = result.csv(request);
  EXPECT_NE(csv.find("image,joint1_deg,camera.p0.u,camera.p0.v"), std::string::npos);
  EXPECT_NE(csv.find("\na.png,10,"), std::string::npos);
  EXPECT_EQ(csv.find("b.png"), std::string::npos);
  EXPECT_NE(result.text().find("b.png"), std::string::npos);

  // Stopped before the second image (Ctrl-C): what was done is kept and said.
  int calls = 0;
  request.stop_requested = [&calls] { return calls++ >= 1; };
  const DetectResult stopped = detect_images(request);
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_EQ(stopped.records.size(), 1u);
  EXPECT_NE(stopped.text().find("interrupted"), std::string::npos);
}

TEST(Detect, APosesFileWithoutImagesOrWithABadValueIsRefusedWithItsLine) {
  TempFolder folder;
  {
    std::ofstream(folder.file("no-image.csv")) << "file,joint1\na.png,1\n";
    std::ofstream(folder.file("bad.csv")) << "image,joint1\na.png,1\nb.png,x\n";
    std::ofstream(folder.file("twice.csv")) << "image,joint1\na.png,1\na.png,2\n";
    std::ofstream(folder.file("missing.csv")) << "image,joint1\na.png,1\nc.png,2\n";
    std::ofstream(folder.file("a.png")) << "a";
    std::ofstream(folder.file("b.png")) << "b";
  }
  const auto message = [](const std::string& path) {
    try {
      read_image_poses(path);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(folder.file("no-image.csv")).find("no-image.csv:1: no column 'image'"),
            std::string::npos);
  EXPECT_NE(message(folder.file("bad.csv")).find("bad.csv:3: column 'joint1': 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(message(folder.file("twice.csv")).find("twice.csv:3: image 'a.png' is named twice"),
            std::string::npos);
  EXPECT_NE(message(folder.file("missing.csv")).find("missing.csv:3: image 'c.png': no such file"),
            std::string::npos);
}

}  // namespace
}  // namespace kincal::vision
