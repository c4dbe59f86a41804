// Model files: round trip, calibrated values as input, and malformed files.

#include "kincal/models/model_io.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

std::string load_error(const std::string& text) {
  // One file per process: ctest runs the tests of this file in parallel processes.
  const auto path = std::filesystem::temp_directory_path() /
                    ("kincal-model-io-test-" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << text;
  try {
    load_model(path.string());
  } catch (const std::invalid_argument& e) {
    std::filesystem::remove(path);
    return std::string(e.what()).substr(path.string().size());
  }
  std::filesystem::remove(path);
  return "(no error)";
}

TEST(ModelIo, PresetRoundTripsExactly) {
  auto preset = make_cube_hexapod();
  preset->parameters().set_free("gauge.offset", true);
  const VectorXd values = preset->parameters().nominal_values();
  const auto j = model_to_json(*preset, values);
  EXPECT_EQ(j["format"], "kincal-model");
  EXPECT_EQ(j["units"], "mm");
  EXPECT_EQ(j["mechanism"]["legs"].size(), 6u);
  EXPECT_EQ(j["free"].size(), 25u);
  const auto back = model_from_json(nlohmann::ordered_json::parse(j.dump()), "M.json");
  EXPECT_EQ(back->parameters().names(), preset->parameters().names());
  EXPECT_EQ(back->parameters().nominal_values(), values);
  EXPECT_EQ(back->parameters().free_indices(), preset->parameters().free_indices());
  EXPECT_EQ(back->mechanism().home_pose().translation, Vector3d(0, 0, 410));
  EXPECT_EQ(model_to_json(*back, values).dump(), j.dump());
}

TEST(ModelIo, CalibratedValuesAndARotatedHomePoseAreValidInput) {
  auto preset = make_cube_hexapod();
  VectorXd values = preset->parameters().nominal_values();
  for (int i = 0; i < values.size(); ++i) values[i] += 0.001 * (i + 1);
  auto j = model_to_json(*preset, values);
  j["mechanism"]["home_pose"]["rotation_zyx_deg"] = {1.5, -2.0, 30.0};
  const auto model = model_from_json(j, "C.json");
  EXPECT_NEAR((model->parameters().nominal_values() - values).norm(), 0, 1e-12);
  const Vector3d zyx = euler_zyx(model->mechanism().home_pose().rotation) * 180 / M_PI;
  EXPECT_NEAR(zyx[0], 30.0, 1e-12);
  EXPECT_NEAR(zyx[1], -2.0, 1e-12);
  EXPECT_NEAR(zyx[2], 1.5, 1e-12);
  const auto copy = model_with_values(*model, values);
  EXPECT_EQ(copy->parameters().free_indices(), preset->parameters().free_indices());
}

TEST(ModelIo, HandWrittenFreeListMayUsePatterns) {
  auto j = model_to_json(*make_cube_hexapod(), make_cube_hexapod()->parameters().nominal_values());
  j["free"] = {"leg?.offset", "gauge.*"};
  const auto model = model_from_json(j, "M.json");
  EXPECT_EQ(model->parameters().num_free(), 6 + 7);
}

TEST(ModelIo, PriorStdIsPerParameterAndRoundTrips) {
  auto j = model_to_json(*make_cube_hexapod(), make_cube_hexapod()->parameters().nominal_values());
  EXPECT_FALSE(j.contains("prior_std"));  // no prior unless stated
  j["prior_std"] = {{"leg?.base.*", 0.5}, {"gauge.offset", 2.0}};
  const auto model = model_from_json(j, "M.json");
  int with_prior = 0;
  for (const auto& p : model->parameters().all()) with_prior += p.has_prior();
  EXPECT_EQ(with_prior, 6 * 3 + 1);
  EXPECT_EQ(model->parameters()[model->parameters().index_of("leg3.base.y")].prior_std, 0.5);
  EXPECT_FALSE(model->parameters()[model->parameters().index_of("leg3.platform.y")].has_prior());
  const auto back =
      model_from_json(model_to_json(*model, model->parameters().nominal_values()), "M2.json");
  for (int i = 0; i < model->parameters().size(); ++i)
    EXPECT_EQ(back->parameters()[i].prior_std, model->parameters()[i].prior_std);
  // 0, and a subnormal std whose precision 1/std^2 is infinite, are refused where they stand.
  for (const double bad : {0.0, 1e-320, 1e-151, 1e151}) {
    j["prior_std"] = {{"gauge.offset", bad}};
    EXPECT_THROW(model_from_json(j, "M.json"), std::invalid_argument) << bad;
    try {
      model_from_json(j, "M.json");
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                "M.json: prior_std.gauge.offset: expected a prior std between 1e-150 and 1e150 "
                "(omit it for no prior)");
    }
  }
  j["prior_std"] = {{"gauge.offset", 1e-150}};
  EXPECT_EQ(model_from_json(j, "M.json")
                ->parameters()[model->parameters().index_of("gauge.offset")]
                .prior_std,
            1e-150);
}

TEST(ModelIo, MalformedFilesNameFileFieldAndExpectation) {
  const auto good =
      model_to_json(*make_cube_hexapod(), make_cube_hexapod()->parameters().nominal_values());
  auto edit = [&](auto change) {
    auto j = good;
    change(j);
    return j.dump();
  };
  using J = nlohmann::ordered_json;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\n  \"format\": \"kincal-model\",\n  oops\n}", ": malformed JSON: parse error at line 3"},
      {"", ": malformed JSON"},
      {"[1, 2]", ": expected a JSON object"},
      {edit([](J& j) { j["format"] = "other"; }), ": format: expected \"kincal-model\""},
      {edit([](J& j) { j["version"] = 2; }), ": version: expected 1, got 2"},
      {edit([](J& j) { j["units"] = "inch"; }), ": units: expected \"mm\""},
      {edit([](J& j) { j.erase("sensors"); }), ": missing key 'sensors'"},
      {edit([](J& j) { j["fre"] = J::array(); }), ": unknown key 'fre'"},
      {edit([](J& j) { j["mechanism"]["type"] = "delta"; }),
       ": mechanism.type: unknown mechanism type 'delta' (available: hexapod-6ups"},
      {edit([](J& j) { j["mechanism"]["legs"].erase(5); }),
       ": mechanism.legs: expected an array of 6 leg objects"},
      {edit([](J& j) {
         j["mechanism"]["legs"][2]["base"] = {1, 2};
       }),
       ": mechanism.legs[2].base: expected an array of 3 numbers"},
      {edit([](J& j) { j["mechanism"]["legs"][2]["base"][1] = "x"; }),
       ": mechanism.legs[2].base[1]: expected a number"},
      {edit([](J& j) { j["mechanism"]["legs"][0]["ofset"] = 1; }),
       ": mechanism.legs[0]: unknown key 'ofset'"},
      {edit([](J& j) { j["mechanism"]["legs"][1]["name"] = "leg7"; }),
       ": mechanism.legs[1].name: expected \"leg2\""},
      {edit([](J& j) { j["mechanism"]["home_pose"].erase("position"); }),
       ": mechanism.home_pose: missing key 'position'"},
      {edit([](J& j) { j["sensors"][0]["type"] = "laser"; }),
       ": sensors[0].type: unknown sensor type 'laser' (available: length-gauge"},
      {edit([](J& j) { j["sensors"][0]["name"] = "a,b"; }), ": sensors[0].name: expected"},
      {edit([](J& j) { j["free"].push_back("leg9.*"); }),
       ": free[24]: parameter pattern 'leg9.*' matches no parameter"},
      {edit([](J& j) { j["free"] = "all"; }), ": free: expected an array"},
      // A sensor named like a leg would share its parameter names and its column.
      {edit([](J& j) { j["sensors"][0]["name"] = "leg1"; }),
       ": sensors: duplicate parameter name 'leg1.base.x'; expected a different sensor name"},
      {edit([](J& j) { j["sensors"].push_back(j["sensors"][0]); }),
       ": sensors[1].name: 'gauge' is already used by another sensor"},
      {edit([](J& j) { j["sensors"][0]["name"] = "g*"; }), ": sensors[0].name: expected"},
      // nlohmann reports an out-of-range number as its own exception, not a parse error.
      {"{\"format\": \"kincal-model\", \"version\": 1, \"units\": \"mm\", \"x\": 1e999}",
       ": unreadable JSON: number overflow parsing '1e999'"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string what = load_error(text);
    EXPECT_EQ(what.rfind(expected, 0), 0u) << "expected '" << expected << "', got '" << what << "'";
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

// nlohmann keeps the last of two equal keys: a second "free" turned 24 free parameters into 1.
TEST(ModelIo, ARepeatedKeyIsAnError) {
  std::string text =
      model_to_json(*make_cube_hexapod(), make_cube_hexapod()->parameters().nominal_values())
          .dump(2);
  text.insert(text.rfind('}'), ",\n  \"free\": [\"gauge.offset\"]\n");
  const std::string what = load_error(text);
  EXPECT_NE(what.find("key 'free' appears twice in the top-level object"), std::string::npos)
      << what;
}

// The release binary crashed (stack overflow in the parser and in dump()) from a nesting
// depth of about 60,000, a file of 120 KB.
TEST(ModelIo, DeepNestingIsAnErrorNotACrash) {
  const std::string deep = std::string(200'000, '[') + std::string(200'000, ']');
  EXPECT_EQ(load_error(deep),
            ": line 1, column 65: nesting deeper than 64 levels of objects and "
            "arrays; expected at most 64");
  EXPECT_NE(load_error("{\"format\": " + deep + "}").find("nesting deeper than 64"),
            std::string::npos);
}

// At a depth of 40,000 the message quoted the whole value: an 80 KB line.
TEST(ModelIo, MessagesQuoteShortExcerptsOfLongValues) {
  const auto good =
      model_to_json(*make_cube_hexapod(), make_cube_hexapod()->parameters().nominal_values());
  std::string long_array = "[";
  for (int i = 0; i < 20'000; ++i) long_array += (i ? ",1" : "1");
  long_array += "]";
  auto with = [&](const std::string& key, const std::string& value) {
    std::string text = good.dump();
    const auto at = text.find("\"" + key + "\":");
    const auto end = text.find_first_of(",}", text.find(':', at));
    return text.substr(0, at) + "\"" + key + "\":" + value + text.substr(end);
  };
  for (const std::string& text :
       {with("format", long_array),
        with("version", "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]"),
        with("units", "\"" + std::string(50'000, 'u') + "\""),
        with("format", "\"" + std::string(50'000, 'f') + "\"")}) {
    const std::string what = load_error(text);
    EXPECT_LT(what.size(), 200u) << what.substr(0, 300);
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

TEST(ModelIo, MissingFileIsAnError) {
  EXPECT_THROW(load_model("/nonexistent/M.json"), std::invalid_argument);
}

// An ifstream opens a directory and fails on the first read with a message naming no file.
TEST(ModelIo, DirectoryIsNamedAsSuch) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("kincal-model-dir-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string what = "(no error)";
  try {
    load_model(dir.string());
  } catch (const std::invalid_argument& e) {
    what = e.what();
  }
  std::filesystem::remove(dir);
  EXPECT_EQ(what, dir.string() + ": is a directory, expected a model file (JSON)");
}

}  // namespace
}  // namespace kincal
