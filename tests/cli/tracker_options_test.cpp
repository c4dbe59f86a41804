// `kincal model --urdf` with the tracker's starting frame and a pose tracker's marker given on
// the command line (issue 40): written into the model file in its units, refused where they
// do not belong.

#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace {

using kincal::testing::run_cli;

std::string ur5_urdf() {
  const char* source = std::getenv("KINCAL_SOURCE_DIR");
  return std::string(source ? source : ".") + "/examples/ur5-laser-tracker/ur5.urdf";
}

TEST(TrackerOptions, FrameAndTargetGoIntoTheModelFile) {
  const auto r = run_cli("model --urdf " + ur5_urdf() +
                         " --tip flange --sensor pose-tracker --frame 1000,200,0,0,0,90"
                         " --target 0,0,50,0,90,0 --out -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto sensor = nlohmann::json::parse(r.out)["sensors"][0];
  EXPECT_EQ(sensor["frame"]["position"], nlohmann::json({1000.0, 200.0, 0.0}));
  EXPECT_EQ(sensor["frame"]["rotation_zyx_deg"], nlohmann::json({0.0, 0.0, 90.0}));
  EXPECT_EQ(sensor["marker"]["position"], nlohmann::json({0.0, 0.0, 50.0}));
  EXPECT_EQ(sensor["marker"]["rotation_zyx_deg"], nlohmann::json({0.0, 90.0, 0.0}));

  const auto point = run_cli("model --urdf " + ur5_urdf() +
                             " --tip flange --frame 10,20,30,0,0,0 --point 0,0,31 --out -");
  ASSERT_EQ(point.exit_code, 0) << point.err;
  const auto tracker = nlohmann::json::parse(point.out)["sensors"][0];
  EXPECT_EQ(tracker["frame"]["position"], nlohmann::json({10.0, 20.0, 30.0}));

  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {" --tip flange --target 0,0,50,0,90,0", "--target is a pose tracker's marker"},
           {" --tip flange --frame 1,2,3", "--frame"},
           {" --tip flange --sensor pose-tracker --point 0,0,1",
            "a pose tracker's marker is --target"}}) {
    const auto bad = run_cli("model --urdf " + ur5_urdf() + args + " --out -");
    EXPECT_EQ(bad.exit_code, 2) << args;
    EXPECT_NE(bad.err.find(says), std::string::npos) << bad.err;
  }
  const auto preset = run_cli("model --preset ur5-urdf --frame 1,2,3,0,0,0");
  EXPECT_EQ(preset.exit_code, 2);
  EXPECT_NE(preset.err.find("--frame needs --urdf"), std::string::npos) << preset.err;
}

}  // namespace
