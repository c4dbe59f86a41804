// kincal export --format camera-info (models/camera_info.cpp): the camera's intrinsics in ROS's
// camera_info YAML, and a model without exactly one camera refused in one sentence.

#include <gtest/gtest.h>

#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/models/export_formats.hpp"

namespace kincal {
namespace {

TEST(CameraInfo, HoldsTheIntrinsicsInOpenCVsOrder) {
  const auto model = ModelRegistry::global().make_preset("ur5-urdf-camera");
  const std::string yaml = export_model(*model, "camera-info", {"M.json", ""});
  EXPECT_NE(yaml.find("image_width: 1280\nimage_height: 1024\ncamera_name: camera\n"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("  data: [1200, 0, 640, 0, 1200, 512, 0, 0, 1]\n"), std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  "
                      "cols: 5\n  data: [-0.080000000000000002, 0.050000000000000003, 0, 0, 0]"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("  data: [1200, 0, 640, 0, 0, 1200, 512, 0, 0, 0, 1, 0]\n"),
            std::string::npos)
      << yaml;
}

TEST(CameraInfo, AModelWithoutOneCameraIsRefused) {
  const auto model = ModelRegistry::global().make_preset("cube-hexapod");
  try {
    export_model(*model, "camera-info", {"M.json", ""});
    FAIL() << "exported a camera of a model without one";
  } catch (const ExportError& e) {
    EXPECT_STREQ(e.what(), "camera-info writes one camera, and the model has 0");
  }
}

}  // namespace
}  // namespace kincal
