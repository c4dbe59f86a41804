// A misspelt command or option is answered with the nearest one (issue 40's frictions).

#include <gtest/gtest.h>

#include "cli_runner.hpp"

namespace {

using kincal::testing::run_cli;

TEST(DidYouMean, AMisspeltCommandOrOptionNamesTheNearest) {
  const auto command = run_cli("calibrat --model m.json");
  EXPECT_EQ(command.exit_code, 2);
  EXPECT_NE(command.err.find("unknown command 'calibrat'; did you mean 'calibrate'?"),
            std::string::npos)
      << command.err;
  const auto option = run_cli("calibrate --seeed 3");
  EXPECT_EQ(option.exit_code, 2);
  EXPECT_NE(option.err.find("unrecognised option '--seeed'; did you mean --seed?"),
            std::string::npos)
      << option.err;
  const auto far = run_cli("calibrate --frobnicate 3");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
  const auto list = run_cli("list --jsno -");
  EXPECT_NE(list.err.find("did you mean --json?"), std::string::npos) << list.err;
}

}  // namespace
