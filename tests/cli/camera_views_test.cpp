// kincal calibrate with a camera: the reprojection error per view in the text and JSON
// reports, and the page for people drawing each view on its image (named by the data's
// `image` column, as kincal detect writes it), or on a blank frame with a note when the
// images cannot be read.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"

namespace kincal::testing {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Simulated views of the eye-to-hand UR5 with an `image` column v<k>.pgm in front; returns
// the number of views.
int write_views(const TempDir& dir) {
  const CliResult model = run_cli("model --preset ur5-urdf-camera --out " + dir / "M.json");
  EXPECT_EQ(model.exit_code, 0) << model.err;
  const CliResult simulated = run_cli(
      "simulate --preset ur5-urdf-camera --poses 8 --noise-half-width 0.5px --param-error "
      "0.1mm,0.0005rad --validation 1 --seed 3 --write-data " +
      dir / "sim.csv");
  EXPECT_EQ(simulated.exit_code, 0) << simulated.err;
  std::istringstream in(read(dir / "sim.csv"));
  std::ofstream out(dir / "views.csv");
  std::string line;
  int views = 0;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << '\n';
      continue;
    }
    out << (header ? std::string("image") : "v" + std::to_string(views++) + ".pgm") << ',' << line
        << '\n';
    header = false;
  }
  return views;
}

// A small grey image (the page only shows it).
void write_image(const std::string& path) {
  std::ofstream pgm(path, std::ios::binary);
  pgm << "P5\n64 48\n255\n" << std::string(64 * 48, '\x80');
}

TEST(CliCameraViews, ReportsTheReprojectionErrorPerViewAndDrawsEachViewOnItsImage) {
  TempDir dir("camera-views");
  const int views = write_views(dir);
  ASSERT_EQ(views, 8);
  std::filesystem::create_directories(dir / "images");
  for (int k = 0; k < views; ++k) write_image(dir / ("images/v" + std::to_string(k) + ".pgm"));
  const std::string calibrate = "calibrate --model " + dir / "M.json" + " --data " +
                                dir / "views.csv" + " --noise-std 0.3px --fix 'camera.*' --json " +
                                dir / "R.json" + " --html " + dir / "R.html";
  const CliResult run = run_cli(calibrate + " --images " + dir / "images");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("reprojection error of camera: "), std::string::npos) << run.out;
  const auto report = nlohmann::json::parse(read(dir / "R.json"));
  ASSERT_TRUE(report.contains("camera_views")) << report.dump();
  const auto& camera = report["camera_views"][0];
  ASSERT_EQ(camera["views"].size(), static_cast<std::size_t>(views));
  EXPECT_EQ(camera["views"][3]["image"], "v3.pgm");
  EXPECT_EQ(camera["views"][3]["label"].get<std::string>().rfind(dir / "views.csv:", 0), 0u);
  // Per point, the RMS distance is sqrt(2) times the per-coordinate RMS of the residuals.
  EXPECT_NEAR(camera["rms_px"].get<double>(), std::sqrt(2.0) * report["residual_rms"].get<double>(),
              1e-9 * camera["rms_px"].get<double>());
  const std::string html = read(dir / "R.html");
  EXPECT_NE(html.find("id=\"camera-views\""), std::string::npos);
#if KINCAL_WITH_VISION
  EXPECT_EQ(count(html, "<image "), views);
  EXPECT_EQ(count(html, "href=\"data:image/jpeg;base64,"), views);
  EXPECT_EQ(count(html, "class=\"residual\""), count(html, "class=\"seen\""));

  // Without the images at hand: the views on blank frames, and a note that says so.
  const CliResult blank = run_cli(calibrate);  // the images are not beside the data
  ASSERT_EQ(blank.exit_code, 0) << blank.err;
  EXPECT_NE(blank.err.find("8 image(s) named in the data not read"), std::string::npos)
      << blank.err;
  const std::string blank_html = read(dir / "R.html");
  EXPECT_EQ(count(blank_html, "<image "), 0);
  EXPECT_EQ(count(blank_html, "class=\"blank\""), views);
#else
  EXPECT_EQ(count(html, "<image "), 0);
  EXPECT_NE(run.err.find("built without OpenCV"), std::string::npos) << run.err;
#endif
}

}  // namespace
}  // namespace kincal::testing
