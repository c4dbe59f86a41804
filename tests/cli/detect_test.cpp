// kincal detect from the command line: images and poses in, a measurement file out, and bad
// input as one line with nothing written (vision/detect.hpp does the work; its own tests draw
// the images). Built without OpenCV, the command says what to install (json_format_test).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli_runner.hpp"

#if KINCAL_WITH_VISION

namespace kincal::testing {
namespace {

// A chessboard of 6 x 8 squares of `square` px (5 x 7 inner corners) on a white page, as a PGM.
void write_board(const std::string& path, int square) {
  std::ofstream pgm(path, std::ios::binary);
  pgm << "P5\n640 480\n255\n";
  const int left = 320 - 4 * square, top = 240 - 3 * square;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const bool on_board = x >= left && x < left + 8 * square && y >= top && y < top + 6 * square;
      const int c = (x - left) / square, r = (y - top) / square;
      pgm.put(static_cast<char>(on_board && (r + c) % 2 == 0 ? 0 : 255));
    }
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliDetect, WritesARowPerImageWithTheTargetAndSaysWhatBecameOfTheOthers) {
  TempDir dir("detect");
  write_board(dir / "a.pgm", 40);
  write_board(dir / "b.pgm", 30);
  { std::ofstream(dir / "c.pgm") << "not an image"; }
  { std::ofstream(dir / "poses.csv") << "image,joint1_deg\na.pgm,1\nb.pgm,2\nc.pgm,3\n"; }
  const CliResult run = run_cli("detect --target chessboard:5x7:20mm --poses " + dir / "poses.csv" +
                                " --out " + dir / "V.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("2 of 3 images with the target"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("unreadable"), std::string::npos) << run.out;
  const std::string csv = read(dir / "V.csv");
  EXPECT_NE(csv.find("image,joint1_deg,camera.p0.u,camera.p0.v"), std::string::npos);
  EXPECT_NE(csv.find("\na.pgm,1,"), std::string::npos);
  EXPECT_NE(csv.find("\nb.pgm,2,"), std::string::npos);
  EXPECT_EQ(csv.find("c.pgm"), std::string::npos);
}

TEST(CliDetect, BadInputIsOneLineAndNothingIsWritten) {
  TempDir dir("detect-bad");
  write_board(dir / "a.pgm", 40);
  { std::ofstream(dir / "poses.csv") << "image,joint1\na.pgm,1\nmissing.pgm,2\n"; }
  const auto fails = [&](const std::string& args, const std::string& expected) {
    const CliResult run = run_cli("detect " + args);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_NE(run.err.find(expected), std::string::npos) << args << ": " << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "V.csv")) << args;
  };
  fails("--images " + dir.path().string() + " --out " + dir / "V.csv", "--target is required");
  fails("--target chessboard:5x7 --images " + dir.path().string() + " --out " + dir / "V.csv",
        "--target: target 'chessboard:5x7'");
  fails("--target chessboard:5x7:20mm --poses " + dir / "poses.csv" + " --out " + dir / "V.csv",
        "missing.pgm");
  fails("--target chessboard:5x7:20mm --images " + dir.path().string() + " --out " + dir / "a.pgm",
        "a.pgm");
  fails("--target chessboard:5x7:20mm --images " + dir.path().string() + " --out " + dir / "V.csv" +
            " --gate -1px",
        "--gate");
}

TEST(CliDetect, AStartingModelThatCannotBeMadeKeepsTheTableAndExitsOne) {
  TempDir dir("detect-start");
  write_board(dir / "a.pgm", 40);
  const CliResult run =
      run_cli("detect --target chessboard:5x7:20mm --images " + dir.path().string() + " --out " +
              dir / "V.csv" + " --start-model " + dir / "S.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("kincal detect: no starting model: "), std::string::npos) << run.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "V.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "S.json"));
}

TEST(CliDetect, NoImageWithTheTargetIsAFailureThatWritesNothing) {
  TempDir dir("detect-none");
  { std::ofstream(dir / "blank.pgm") << "P5\n64 48\n255\n" << std::string(64 * 48, '\xc8'); }
  const CliResult run = run_cli("detect --target chessboard:5x7:20mm --images " +
                                dir.path().string() + " --out " + dir / "V.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("found in none of the 1 images"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "V.csv"));
}

}  // namespace
}  // namespace kincal::testing

#endif
