// The name policy (framework/kinematics/names.hpp): what kincal accepts as a name is what its
// readers accept back, is no spreadsheet formula and cannot drive a terminal.

#include "kincal/framework/kinematics/names.hpp"

#include <gtest/gtest.h>

#include <string>

namespace kincal {
namespace {

TEST(Names, AcceptsTheNamesRealMachinesUse) {
  for (const char* name : {"leg1", "joint_6", "shoulder_pan_joint", "panda_joint1", "arm/joint2",
                           "gauge", "épaule", "关节1", "j(1)"})
    EXPECT_EQ(name_problem(name), "") << name;
  EXPECT_EQ(name_problem("tracker.x", NameKind::kColumn), "");
  EXPECT_EQ(name_problem(std::string(kMaxNameBytes, 'j')), "");
}

TEST(Names, RefusesWhatWouldNotReadBackOrWouldHarm) {
  const std::pair<std::string, std::string> cases[] = {
      {"", "is empty"},
      {std::string("a\0b", 3), "contains the control character U+0000"},
      {std::string(kMaxNameBytes + 1, 'j'), "is 129 bytes long, more than the 128 allowed"},
      {std::string(70000, 'j'), "is 70000 bytes long, more than the 128 allowed"},
      {"j\nk", "contains the control character U+000A"},
      {"j\x1b[31m", "contains the control character U+001B"},
      {"j\a", "contains the control character U+0007"},
      {"j\x7f", "contains the control character U+007F"},
      {"j\xc2\x9b", "contains the control character U+009B"},  // C1 CSI
      {"\xe9t\xe9", "is not valid UTF-8"},
      {"=cmd|'/Ccalc'!A0", "starts with '='"},
      {"@SUM(1+1)", "starts with '@'"},
      {"+1", "starts with '+'"},
      {"-1", "starts with '-'"},
      {"a,b", "contains ','"},
      {"a;b", "contains ';'"},
      {"a b", "contains ' '"},
      {"a.b", "contains '.'"},
      {"a*", "contains '*'"},
  };
  for (const auto& [name, problem] : cases)
    EXPECT_EQ(name_problem(name).rfind(problem, 0), 0u)
        << "name '" << name << "': " << name_problem(name);
  EXPECT_NE(name_problem("=x.y", NameKind::kColumn), "");
}

// A description or label (a plug-in's preset description, a constraint's label): spaces and
// punctuation are fine, what drives a terminal or breaks the line is not.
TEST(Names, TextIsOnePrintableLine) {
  EXPECT_EQ(text_problem("Puma 560 (Corke & Armstrong-Helouvry, 1994); x, y: 5 mm"), "");
  EXPECT_EQ(text_problem("=a formula is text here"), "");
  EXPECT_EQ(text_problem("clears \x1b[2J"), "contains the control character U+001B");
  EXPECT_EQ(text_problem("two\nlines"), "contains the control character U+000A");
  EXPECT_EQ(text_problem("csi \xc2\x9b"), "contains the control character U+009B");
  EXPECT_EQ(text_problem("\xe9t\xe9"), "is not valid UTF-8");
  EXPECT_EQ(text_problem(""), "is empty");
  EXPECT_NE(text_problem(std::string(kMaxTextBytes + 1, 'a')), "");
  EXPECT_EQ(text_problem(std::string(kMaxTextBytes, 'a')), "");
}

TEST(Names, Utf8) {
  EXPECT_TRUE(is_valid_utf8("plain.csv"));
  EXPECT_TRUE(is_valid_utf8("données.csv"));
  EXPECT_FALSE(is_valid_utf8("\xe9t\xe9.csv"));
  EXPECT_FALSE(is_valid_utf8("\xc0\xaf"));                  // overlong '/'
  EXPECT_FALSE(is_valid_utf8("\xed\xa0\x80"));              // a surrogate
  EXPECT_FALSE(is_valid_utf8(std::string("\xe2\x82", 2)));  // cut short
}

}  // namespace
}  // namespace kincal
