// libFuzzer target: what kincal detect reads besides images (vision/detect.hpp,
// vision/target_detection.hpp): the target's description (the input's first line) and the
// poses file (the rest). Each must be read or refused with std::invalid_argument carrying one
// short line; what is read must be consistent (a value per column per image, every value a
// finite number, no image twice).

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>

#include "kincal/vision/detect.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_detect_inputs: %s: %s\n", what, detail.c_str());
  std::abort();
}

void check_message(const std::string& what, const std::string& start) {
  if (what.rfind(start, 0) != 0) fail("message does not say what it is about", what);
  if (what.find('\n') != std::string::npos) fail("message is not one line", what);
  if (what.size() > 600) fail("message too long", what);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const auto newline = input.find('\n');
  const std::string first = input.substr(0, newline);
  try {
    const kincal::vision::TargetSpec target = kincal::vision::TargetSpec::parse(first);
    if (target.num_points() < 4) fail("a target of fewer than 4 points", first);
    if (!(target.spacing > 0) || !std::isfinite(target.spacing)) fail("spacing", first);
    if (target.camera_target().points.size() != static_cast<std::size_t>(target.num_points()))
      fail("points", first);
  } catch (const std::invalid_argument& e) {
    if (first.size() < 200) check_message(e.what(), "");
  }
  if (newline == std::string::npos) return 0;
  std::istringstream in(input.substr(newline + 1));
  try {
    const kincal::vision::ImagePoses poses =
        kincal::vision::parse_image_poses(in, "P.csv", "images", false);
    if (poses.images.empty()) fail("no image but no error", "");
    std::set<std::string> names(poses.images.begin(), poses.images.end());
    if (names.size() != poses.images.size()) fail("an image twice", "");
    for (const auto& values : poses.values) {
      if (values.size() != poses.columns.size()) fail("values per image", "");
      for (const auto& v : values)
        if (!std::isfinite(std::strtod(v.c_str(), nullptr))) fail("a value not a number", v);
    }
  } catch (const std::invalid_argument& e) {
    check_message(e.what(), "P.csv");
  }
  return 0;
}
