// "Did you mean": the distance and the choice of the nearest known name.

#include <gtest/gtest.h>

#include "kincal/framework/base/nearest_name.hpp"

namespace kincal {
namespace {

TEST(NearestName, DistanceCountsEditsAndSwaps) {
  EXPECT_EQ(edit_distance("seed", "seed"), 0);
  EXPECT_EQ(edit_distance("seeed", "seed"), 1);
  EXPECT_EQ(edit_distance("sede", "seed"), 1);  // a swap
  EXPECT_EQ(edit_distance("", "abc"), 3);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
}

TEST(NearestName, SuggestsOnlyWhatLooksLikeAMisspelling) {
  const std::vector<std::string> commands = {"calibrate", "validate", "compare", "compensate",
                                             "design"};
  EXPECT_EQ(nearest_name("calibrat", commands), "calibrate");
  EXPECT_EQ(nearest_name("valdiate", commands), "validate");
  EXPECT_EQ(nearest_name("compenstae", commands), "compensate");
  EXPECT_EQ(nearest_name("frobnicate", commands), "");
  EXPECT_EQ(nearest_name("desi", commands), "design");  // a prefix of one name
  EXPECT_EQ(nearest_name("com", commands), "");         // a prefix of two: no guess
  EXPECT_EQ(nearest_name("", commands), "");
  EXPECT_EQ(nearest_name("seeed", {"seed", "solver", "starts"}), "seed");
}

}  // namespace
}  // namespace kincal
