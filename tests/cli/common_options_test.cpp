// The shared CLI helpers (cli/common_options.hpp, cli/progress.hpp) in-process.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

// solver-suite's estimate (issue 21 item 3): a slow last backend keeps time on the clock
// until its end, where the rate of all runs so far said "about 0 s left".
TEST(CliProgress, TheTimeLeftWeighsEachStageBySpeed) {
  EXPECT_TRUE(std::isnan(staged_time_left({}, 4, 2)));
  EXPECT_TRUE(std::isnan(staged_time_left({{}}, 4, 2)));
  // First stage under way: its own rate, for its rest and the stages to come.
  EXPECT_DOUBLE_EQ(staged_time_left({{1, 1}}, 4, 2), 2 + 4);
  // Two fast stages (1 s per item) done, the third 10 times slower: 10 s per item left.
  const std::vector<double> fast = {1, 1, 1, 1};
  EXPECT_DOUBLE_EQ(staged_time_left({fast, fast, {10}}, 4, 3), 30);
  EXPECT_DOUBLE_EQ(staged_time_left({fast, fast, {10, 10, 10}}, 4, 3), 10);
  // Items of different cost: item 3 costs 4 times item 0 in every stage so far.
  const std::vector<double> uneven = {1, 1, 1, 4};
  EXPECT_DOUBLE_EQ(staged_time_left({uneven, {5, 5, 5}}, 4, 2), 20);
  // A stage not started yet is taken at the mean factor of those started (1 and 10 here).
  EXPECT_DOUBLE_EQ(staged_time_left({fast, {10, 10, 10, 10}}, 4, 3), 4 * 5.5);
  EXPECT_EQ(Progress::line(3, 4, "runs", 12.0, 0.2), "3/4 runs, 12 s elapsed, under 1 s left");
  EXPECT_EQ(Progress::line(3, 4, "runs", 12.0, 5.0), "3/4 runs, 12 s elapsed, about 5 s left");
}

}  // namespace
}  // namespace kincal::cli
