// The shared CLI helpers (cli/common_options.hpp, cli/progress.hpp) in-process.

#include <gtest/gtest.h>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/progress.hpp"

namespace kincal::cli {
namespace {

TEST(CliDefaults, NumbersAreTheShortestTextThatReadsBack) {
  EXPECT_EQ(default_text(1e-6), "1e-06");
  EXPECT_EQ(default_text(0.1), "0.1");
  EXPECT_EQ(default_text(200), "200");
  EXPECT_EQ(default_text(-2.5e6), "-2500000");
  EXPECT_EQ(default_text(1.0 / 3), "0.3333333333333333");  // 16 digits read back
}

TEST(CliProgress, TheLineGivesTheTimeRemainingFromTheRateSoFar) {
  EXPECT_EQ(Progress::line(0, 4, "trials", 0.2), "0/4 trials, 0 s elapsed");
  EXPECT_EQ(Progress::line(1, 4, "trials", 10.0), "1/4 trials, 10 s elapsed, about 30 s left");
  EXPECT_EQ(Progress::line(100, 500, "trials", 31.0),
            "100/500 trials, 31 s elapsed, about 2 min 4 s left");
  EXPECT_EQ(Progress::line(4, 4, "runs", 12.4), "4/4 runs, 12 s elapsed");
  EXPECT_EQ(duration_text(3725), "1 h 2 min");
}

}  // namespace
}  // namespace kincal::cli
