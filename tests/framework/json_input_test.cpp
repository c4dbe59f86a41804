// JSON that users write (framework/io/json_input.hpp) and quoting it in messages
// (framework/base/message_excerpt.hpp): duplicate keys, nesting and size limits, one-line messages.

#include "kincal/framework/io/json_input.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {
namespace {

std::string parse_error(const std::string& text, const JsonLimits& limits = {}) {
  try {
    (void)parse_json_text(text, "F.json", limits);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

std::string nested(int depth) { return std::string(depth, '[') + std::string(depth, ']'); }

TEST(JsonInput, ParsesAndKeepsKeyOrder) {
  const auto j = parse_json_text("{\"b\": 1, \"a\": [true, null, 2.5, \"x\"]}", "F.json");
  EXPECT_EQ(j.dump(), "{\"b\":1,\"a\":[true,null,2.5,\"x\"]}");
  EXPECT_EQ(parse_json_text("\xEF\xBB\xBF 3", "F.json"), 3);  // a byte order mark is skipped
}

// nlohmann alone keeps the last of two equal keys: a second "free" replaced the first.
TEST(JsonInput, ARepeatedKeyIsAnErrorNamingKeyPlaceAndObject) {
  EXPECT_EQ(parse_error("{\"free\": [\"a\"],\n \"free\": [\"b\"]}"),
            "F.json: line 2, column 7: key 'free' appears twice in the top-level object; expected "
            "each key once (the second would silently replace the first)");
  const std::string nested_twice =
      "{\"mechanism\": {\"legs\": [{}, {}, {\"base\": 1, \"offset\": 0, \"offset\": 1}]}}";
  EXPECT_NE(
      parse_error(nested_twice).find("key 'offset' appears twice in object mechanism.legs[2]"),
      std::string::npos)
      << parse_error(nested_twice);
  // Deep in long keys (found by fuzz_model_file): the path keeps its first and innermost steps.
  std::string deep;
  for (int level = 0; level < 40; ++level)
    deep += "{\"" + std::string(50, 'a' + level % 26) + "\": ";
  deep += "{\"x\": 1, \"x\": 2}" + std::string(40, '}');
  const std::string what = parse_error(deep);
  EXPECT_LT(what.size(), 400u) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos);
  EXPECT_NE(what.find("in object " + std::string(50, 'a') + "..."), std::string::npos) << what;
  EXPECT_NE(what.find("." + std::string(50, 'n') + "; expected"), std::string::npos) << what;
  // The same key in two different objects is fine.
  EXPECT_NO_THROW((void)parse_json_text("[{\"a\": 1}, {\"a\": 2}, {\"b\": {\"a\": 3}}]", "F.json"));
}

TEST(JsonInput, NestingBeyondTheLimitIsAnErrorNotACrash) {
  EXPECT_NO_THROW((void)parse_json_text(nested(64), "F.json"));
  EXPECT_EQ(parse_error(nested(65)),
            "F.json: line 1, column 65: nesting deeper than 64 levels of objects and arrays; "
            "expected at most 64");
  // Deep enough to overflow the stack of a recursive reader or of dump(): stops at the
  // limit, having read 65 bytes of the 2 MB.
  EXPECT_NE(parse_error(nested(1'000'000)).find("nesting deeper than 64"), std::string::npos);
  JsonLimits shallow;
  shallow.max_depth = 2;
  EXPECT_NE(parse_error("{\"a\": {\"b\": []}}", shallow).find("deeper than 2"), std::string::npos);
}

TEST(JsonInput, SizeLimit) {
  JsonLimits small;
  small.max_bytes = 10;
  EXPECT_NO_THROW((void)parse_json_text("[1, 2, 3]", "F.json", small));
  EXPECT_EQ(parse_error("[1, 2, 3, 4]", small),
            "F.json: larger than the limit of 0 MiB (10 bytes) for a JSON file");
}

TEST(JsonInput, SyntaxErrorsAndOverflowKeepNlohmannsPosition) {
  EXPECT_EQ(parse_error("{\"a\": 1,, }")
                .rfind("F.json: malformed JSON: parse error at line 1, "
                       "column 9: syntax error",
                       0),
            0u)
      << parse_error("{\"a\": 1,, }");
  EXPECT_EQ(parse_error("[1e999]"), "F.json: unreadable JSON: number overflow parsing '1e999'");
  // A syntax error after a 100 KB token is still a short line.
  const std::string what = parse_error("[\"" + std::string(100'000, 'x'));
  EXPECT_LT(what.size(), 400u) << what.size();
  EXPECT_EQ(what.find('\n'), std::string::npos);
}

TEST(JsonInput, ReadsFilesWithinTheLimit) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("kincal-json-input-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "F.json").string();
  std::ofstream(path) << "{\"a\": 1}";
  EXPECT_EQ(read_json_file(path, "model file")["a"], 1);
  auto error = [](const std::string& p, const JsonLimits& limits = {}) -> std::string {
    try {
      (void)read_json_file(p, "model file", limits);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error(dir.string()), dir.string() + ": is a directory, expected a model file (JSON)");
  EXPECT_EQ(error(path + ".none"), path + ".none: cannot open model file (missing or unreadable)");
  // A device that never ends is read only up to the limit.
  JsonLimits small;
  small.max_bytes = 1000;
  EXPECT_EQ(error("/dev/zero", small),
            "/dev/zero: larger than the limit of 0 MiB (1000 bytes) for a model file");
  std::filesystem::remove_all(dir);
}

TEST(JsonInput, ExcerptsAreShortSingleLines) {
  nlohmann::ordered_json long_array = nlohmann::ordered_json::array();
  for (int i = 0; i < 10000; ++i) long_array.push_back(i);
  const std::string excerpt = json_excerpt(long_array, 20);
  EXPECT_EQ(excerpt, "[0,1,2,3,4,5,6,7,8,9...");
  EXPECT_EQ(json_excerpt(nlohmann::ordered_json("a\nb")), "\"a\\nb\"");
}

TEST(MessageExcerpt, EscapesControlBytesAndBrokenUtf8AndCuts) {
  EXPECT_EQ(message_excerpt(std::string("336.81\0junk", 11)), "336.81\\x00junk");
  EXPECT_EQ(message_excerpt("a\nb\rc\td"), "a\\x0Ab\\x0Dc\\x09d");
  EXPECT_EQ(message_excerpt("\xEF\xBB\xBFleg1"), "\xEF\xBB\xBFleg1");  // valid UTF-8 kept
  EXPECT_EQ(message_excerpt("±5 µm"), "±5 µm");
  EXPECT_EQ(message_excerpt("\xFF\xC3("), "\\xFF\\xC3(");         // not UTF-8
  EXPECT_EQ(message_excerpt("\xED\xA0\x80"), "\\xED\\xA0\\x80");  // a surrogate
  EXPECT_EQ(message_excerpt("\xC0\xAF"), "\\xC0\\xAF");           // overlong '/'
  EXPECT_EQ(message_excerpt("\xC2\x85"), "\\xC2\\x85");           // C1 line break
  EXPECT_EQ(message_excerpt(std::string(1000, 'x'), 5), "xxxxx...");
  EXPECT_EQ(message_excerpt("abc", 3), "abc");
  // An escape counts as the four characters it shows (a fuzzer found 300 DEL bytes making
  // a 1,200-character message).
  EXPECT_EQ(message_excerpt(std::string(100, '\x7F'), 8), "\\x7F\\x7F...");
}

}  // namespace
}  // namespace kincal
