// Plug-ins in the stock kincal (framework/extension/plugin.hpp): the example plug-in
// (examples/plugin, a five-bar linkage and a laser displacement sensor) through every command a
// user runs, and the ways loading must fail: another kincal version, a name that clashes, not a
// plug-in, a plug-in whose Jacobian has a sign flipped (kincal check names it).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/framework/extension/plugin.hpp"
#include "kincal/framework/kinematics/model_names.hpp"
#include "kincal/framework/kinematics/names.hpp"

namespace kincal::testing {
namespace {

const std::string kFiveBar = KINCAL_FIVE_BAR_PLUGIN;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Plugins, ListShowsThePluginsTypesAndPreset) {
  const auto run = run_cli("list --plugin " + kFiveBar);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(contains(run.out, "five-bar-demo")) << run.out;
  EXPECT_TRUE(contains(run.out, "\nfive-bar ")) << run.out;
  EXPECT_TRUE(contains(run.out, "\nlaser-displacement ")) << run.out;
  // Each added type names its plug-in; a built-in one names none.
  const std::string from_plugin =
      " [plug-in " + std::filesystem::canonical(kFiveBar).string() + "]";
  const auto line_of = [&](const std::string& name) {
    const std::size_t at = run.out.find("\n" + name + " ");
    return at == std::string::npos ? std::string()
                                   : run.out.substr(at + 1, run.out.find('\n', at + 1) - at - 1);
  };
  for (const char* type : {"five-bar-demo", "five-bar", "laser-displacement"})
    EXPECT_TRUE(contains(line_of(type), from_plugin)) << type << ": " << line_of(type);
  EXPECT_FALSE(line_of("hexapod-6ups").empty());
  EXPECT_FALSE(contains(line_of("hexapod-6ups"), "[plug-in")) << line_of("hexapod-6ups");
  const auto json =
      nlohmann::json::parse(run_cli("list sensors --json - --plugin " + kFiveBar).out);
  for (const auto& e : json["sensors"])
    EXPECT_EQ(e["plugin"].is_null(), e["name"] != "laser-displacement") << e.dump();
  // Without the plug-in the stock kincal does not know the type.
  const auto without = run_cli("simulate --preset five-bar-demo");
  EXPECT_EQ(without.exit_code, 2);
  EXPECT_TRUE(contains(without.err, "five-bar-demo")) << without.err;
}

TEST(Plugins, TheEnvironmentNamesPluginsAndFolders) {
  const auto by_file = run_cli("list models", "KINCAL_PLUGIN_PATH=" + kFiveBar + " ");
  ASSERT_EQ(by_file.exit_code, 0) << by_file.err;
  EXPECT_TRUE(contains(by_file.out, "five-bar-demo"));
  // A folder: every *.so in it.
  TempDir dir("plugin-path");
  std::filesystem::copy_file(kFiveBar, dir / "five_bar.so");
  std::ofstream(dir / "README.txt") << "not a plug-in, and not named *.so\n";
  const auto by_folder =
      run_cli("list models", "KINCAL_PLUGIN_PATH=:" + dir.path().string() + ": ");
  ASSERT_EQ(by_folder.exit_code, 0) << by_folder.err;
  EXPECT_TRUE(contains(by_folder.out, "five-bar-demo"));
  const auto missing = run_cli("list models", "KINCAL_PLUGIN_PATH=/no/such/plugin.so ");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(contains(missing.err, "KINCAL_PLUGIN_PATH: '/no/such/plugin.so'")) << missing.err;
  const auto both =
      run_cli("list models --plugin " + kFiveBar, "KINCAL_PLUGIN_PATH=" + kFiveBar + " ");
  EXPECT_EQ(both.exit_code, 0) << "the same file twice is loaded once: " << both.err;
}

TEST(Plugins, SimulateRecoversTheTruthAndTheWorkflowRuns) {
  TempDir dir("plugin-workflow");
  const std::string p = " --plugin " + kFiveBar;
  const auto sim = run_cli("simulate --preset five-bar-demo --noise-half-width 0 --json -" + p);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto report = nlohmann::json::parse(sim.out);
  EXPECT_LT(report["parameter_rms_error_mm"].get<double>(), 1e-6) << sim.out.substr(0, 2000);
  EXPECT_LT(report["parameter_rms_error_rad"].get<double>(), 1e-6) << sim.out.substr(0, 2000);

  const std::string m = dir / "five-bar.json", d = dir / "data.csv", c = dir / "calibrated.json";
  ASSERT_EQ(run_cli("model --preset five-bar-demo --out " + m + p).exit_code, 0);
  ASSERT_EQ(
      run_cli("simulate --model " + m + " --noise-half-width 0 --seed 3 --write-data " + d + p)
          .exit_code,
      0);
  const auto cal = run_cli("calibrate --model " + m + " --data " + d + " --out " + c + p);
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  const auto obs = run_cli("observability --model " + m + " --data " + d + p);
  EXPECT_EQ(obs.exit_code, 0) << obs.err;
  EXPECT_TRUE(contains(obs.out, "rank 10")) << obs.out;
  const auto design = run_cli("design --model " + m + " --poses 12 --candidates 60 " +
                              "--noise-std 0.01mm --out " + dir / "design.csv" + p);
  EXPECT_EQ(design.exit_code, 0) << design.err;

  const auto json = run_cli("export --model " + c + " --format json" + p);
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto exported = nlohmann::json::parse(json.out);
  EXPECT_EQ(exported["mechanism"], "five-bar");
  EXPECT_EQ(exported["description"]["type"], "five-bar");
  EXPECT_EQ(exported["parameters"].size(), 10u);
  EXPECT_EQ(exported["actuators"].size(), 2u);
  // The plug-in's own format, and one nobody registered.
  const auto table = run_cli("export --model " + c + " --format arm-table" + p);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_TRUE(contains(table.out, "\narm2,")) << table.out;
  const auto unknown = run_cli("export --model " + c + " --format dxf" + p);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_TRUE(contains(unknown.err, "expected urdf, csv, json, camera-info, arm-table"))
      << unknown.err;
}

TEST(Plugins, CheckPassesOnThePluginAndNamesAFlippedSign) {
  const auto good = run_cli("check --plugin " + kFiveBar);
  EXPECT_EQ(good.exit_code, 0) << good.out << good.err;
  EXPECT_TRUE(contains(good.out, "pass  preset five-bar-demo: J_pose_params")) << good.out;
  EXPECT_TRUE(contains(good.out, "zero-noise recovery with lm")) << good.out;

  const auto bad = run_cli(std::string("check --plugin ") + KINCAL_FLIPPED_SIGN_PLUGIN);
  EXPECT_EQ(bad.exit_code, 1) << bad.out << bad.err;
  // The flipped entry is d g / d arm<i>.offset: the pose Jacobian names the column.
  EXPECT_TRUE(contains(bad.out, "FAIL  preset five-bar-demo: J_pose_params of the mechanism"))
      << bad.out;
  EXPECT_TRUE(contains(bad.out, ".offset'")) << bad.out;
  EXPECT_TRUE(contains(bad.out, "FAILED: ")) << bad.out;
  // Its sensors are right, and are not blamed.
  EXPECT_TRUE(contains(bad.out, "pass  preset five-bar-demo: J_reading_pose of sensor 'laser_x'"))
      << bad.out;
  // With the residuals' Jacobian wrong, no backend is run to its limit: each recovery fails
  // and says why.
  EXPECT_TRUE(contains(bad.out, "FAIL  preset five-bar-demo: zero-noise recovery with lm"))
      << bad.out;
  EXPECT_TRUE(contains(bad.out, "not run: the Jacobian of the calibration residuals is wrong"))
      << bad.out;
}

TEST(Plugins, AnotherKincalVersionIsRefusedWithAMessage) {
  const auto run = run_cli(std::string("list --plugin ") + KINCAL_WRONG_VERSION_PLUGIN);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_TRUE(contains(run.err, "built against kincal 0.0.0-elsewhere")) << run.err;
  EXPECT_TRUE(contains(run.err, "rebuild the plug-in")) << run.err;
}

TEST(Plugins, ANameClashNamesBoth) {
  const auto builtin = run_cli(std::string("list --plugin ") + KINCAL_CLASH_PLUGIN);
  EXPECT_EQ(builtin.exit_code, 2);
  EXPECT_TRUE(
      contains(builtin.err, "preset 'puma560' (registered by kincal or the program, built in)"))
      << builtin.err;
  EXPECT_TRUE(contains(builtin.err, "test_plugin_clash")) << builtin.err;
  // The same plug-in under two file names: the second clashes with the first.
  TempDir dir("plugin-clash");
  const std::string copy = dir / "copy.so";
  std::filesystem::copy_file(kFiveBar, copy);
  const auto twice = run_cli("list --plugin " + kFiveBar + " --plugin " + copy);
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_TRUE(contains(twice.err, "copy.so")) << twice.err;
  EXPECT_TRUE(contains(twice.err, "mechanism type 'five-bar' (registered by plug-in '"))
      << twice.err;
}

TEST(Plugins, NotAPluginOrNoFileIsOneLine) {
  TempDir dir("plugin-bad");
  const std::string text = dir / "notes.so";
  std::ofstream(text) << "not a shared library\n";
  const auto garbage = run_cli("list --plugin " + text);
  EXPECT_EQ(garbage.exit_code, 2);
  EXPECT_TRUE(contains(garbage.err, "cannot be loaded")) << garbage.err;
  const auto none = run_cli("list --plugin " + dir / "none.so");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_TRUE(contains(none.err, "none.so")) << none.err;
  const auto no_value = run_cli("list --plugin");
  EXPECT_EQ(no_value.exit_code, 2);
  EXPECT_TRUE(contains(no_value.err, "the required argument for option '--plugin' is missing"))
      << no_value.err;
  const auto empty = run_cli("list --plugin ''");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_TRUE(contains(empty.err, "--plugin needs a file")) << empty.err;
  const auto nothing_after_equals = run_cli("list --plugin=");
  EXPECT_EQ(nothing_after_equals.exit_code, 2);
  EXPECT_TRUE(contains(nothing_after_equals.err, "'--plugin'")) << nothing_after_equals.err;
  // A shared library without the entry point.
  const auto other = run_cli("list --plugin /lib/x86_64-linux-gnu/libm.so.6");
  if (std::filesystem::exists("/lib/x86_64-linux-gnu/libm.so.6")) {
    EXPECT_EQ(other.exit_code, 2);
    EXPECT_TRUE(contains(other.err, "not a kincal plug-in")) << other.err;
  }
}

TEST(Plugins, APluginsSolverIsUsedByName) {
  const std::string p = std::string(" --plugin ") + KINCAL_SOLVER_PLUGIN;
  const auto list = run_cli("list solvers" + p);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(contains(list.out, "plugin-gn")) << list.out;
  const auto sim =
      run_cli("simulate --preset planar-3rpr --noise-half-width 0 --solver plugin-gn --json -" + p);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_LT(nlohmann::json::parse(sim.out)["parameter_rms_error_mm"].get<double>(), 1e-6);
}

// The misbehaving plug-in (tests/plugins/misbehaving_plugin.cpp): KINCAL_TEST_PLUGIN_MODE
// chooses how its registration misbehaves; KINCAL_TEST_PLUGIN_MARKER=FILE shows it ran.
const std::string kMisbehaving = KINCAL_MISBEHAVING_PLUGIN;

bool exactly_one_line(const std::string& err) {
  return !err.empty() && err.find('\n') == err.size() - 1;
}

TEST(Plugins, OnlyARealPluginOptionLoadsOne) {
  TempDir dir("plugin-option");
  const std::string marker = dir / "ran";
  const std::string env = "KINCAL_TEST_PLUGIN_MARKER=" + marker + " ";
  ASSERT_EQ(run_cli("model --preset puma560 --out " + dir / "M.json").exit_code, 0);
  // The value of --data, of --out, an operand after --: not plug-ins.
  for (const std::string& args :
       {"calibrate --model " + dir / "M.json" + " --data --plugin=" + kMisbehaving,
        "calibrate --model " + dir / "M.json" + " --data D.csv --out --plugin=" + kMisbehaving,
        "list -- --plugin=" + kMisbehaving}) {
    const auto run = run_cli(args, env);
    EXPECT_EQ(run.exit_code, 2) << args;
    EXPECT_TRUE(exactly_one_line(run.err)) << args << ": " << run.err;
    EXPECT_FALSE(std::filesystem::exists(marker)) << args << " ran the plug-in's code";
  }
  // A real option, wherever it stands among the options.
  const auto real = run_cli("list models --plugin=" + kMisbehaving, env);
  EXPECT_EQ(real.exit_code, 0) << real.err;
  EXPECT_TRUE(contains(real.out, "misbehaving-null")) << real.out;
  EXPECT_TRUE(std::filesystem::exists(marker));
}

TEST(Plugins, WhatAPluginRegistersFollowsTheNamePolicy) {
  for (const auto& [mode, message] : std::vector<std::pair<std::string, std::string>>{
           {"escape-description",
            "the description of preset 'misbehaving-escape' contains the control character "
            "U+001B"},
           {"formula-preset", "preset '=cmd|"},
           {"formula-solver", "solver '=cmd|"}}) {
    const auto run =
        run_cli("list --plugin " + kMisbehaving, "KINCAL_TEST_PLUGIN_MODE=" + mode + " ");
    EXPECT_EQ(run.exit_code, 2) << mode;
    EXPECT_TRUE(exactly_one_line(run.err)) << mode << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "registers a name kincal does not accept")) << run.err;
    EXPECT_TRUE(contains(run.err, "misbehaving")) << run.err;
    EXPECT_FALSE(contains(run.out + run.err, "\x1b")) << mode;
  }
  // A preset whose model names its columns like formulas: refused when made, nothing written.
  TempDir dir("plugin-names");
  const auto sim = run_cli(
      "simulate --preset misbehaving-formula-columns --validation 1 "
      "--write-data " +
      dir / "F.csv" + " --plugin " + kMisbehaving);
  EXPECT_EQ(sim.exit_code, 2);
  EXPECT_TRUE(exactly_one_line(sim.err)) << sim.err;
  EXPECT_TRUE(contains(sim.err,
                       "preset 'misbehaving-formula-columns' makes a model whose sensor "
                       "'=cmd|"))
      << sim.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "F.csv"));
}

TEST(Plugins, WhatAPluginThrowsOrReturnsNullIsOneLineNamingIt) {
  const std::string p = " --plugin " + kMisbehaving;
  struct Case {
    std::string environment, args, message;
  };
  const std::vector<Case> cases = {
      {"KINCAL_TEST_PLUGIN_MODE=throw-int ", "list" + p,
       "its registration threw an exception that is not a std::exception"},
      {"", "simulate --preset misbehaving-throws --validation 1" + p,
       "preset 'misbehaving-throws' threw an exception that is not a std::exception"},
      {"", "simulate --preset misbehaving-null --validation 1" + p,
       "preset 'misbehaving-null' returned null"},
      {"", "simulate --preset puma560 --validation 1 --solver misbehaving-null-solver" + p,
       "solver 'misbehaving-null-solver''s factory returned null"},
      {"", "simulate --preset puma560 --validation 1 --solver misbehaving-throwing-solver" + p,
       "solver 'misbehaving-throwing-solver' threw an exception that is not a std::exception"},
      {"", "simulate --preset misbehaving-throwing-sensor --validation 1" + p,
       "a plug-in threw an exception that is not a std::exception (loaded: '"},
      {"", "simulate --preset misbehaving-nan-jacobian --validation 1" + p,
       "is nan at configuration 1, reading 'tracker.x' of sensor 'tracker'"}};
  for (const Case& c : cases) {
    const auto run = run_cli(c.args, c.environment);
    EXPECT_EQ(run.exit_code, 2) << c.args << ": " << run.err;
    EXPECT_TRUE(exactly_one_line(run.err)) << c.args << ": " << run.err;
    EXPECT_TRUE(contains(run.err, c.message)) << c.args << ": " << run.err;
    EXPECT_TRUE(contains(run.err, "misbehaving")) << c.args << ": " << run.err;
  }
}

// Every built-in preset's model follows the name policy that a plug-in preset's is held to.
TEST(PluginLibrary, BuiltInPresetsAndNamesPassThePolicyPluginsAreHeldTo) {
  for (const auto& preset : ModelRegistry::global().presets()) {
    EXPECT_EQ(model_name_problem(*preset.make()), "") << preset.name;
    EXPECT_EQ(name_problem(preset.name), "") << preset.name;
    EXPECT_EQ(text_problem(preset.description), "") << preset.name;
  }
  for (const auto& type : ModelRegistry::global().mechanisms())
    EXPECT_EQ(text_problem(type.description), "") << type.type;
  for (const auto& type : ModelRegistry::global().sensors())
    EXPECT_EQ(text_problem(type.description), "") << type.type;
}

TEST(Plugins, CheckAllPassesOnEveryBuiltInPresetAndNeedsASubject) {
  const auto all = run_cli("check --all");
  EXPECT_EQ(all.exit_code, 0) << all.out << all.err;
  EXPECT_TRUE(contains(all.out, "pass  preset cube-hexapod: zero-noise recovery with lm"))
      << all.out;
  EXPECT_FALSE(contains(all.out, "FAIL")) << all.out;
  const auto nothing = run_cli("check");
  EXPECT_EQ(nothing.exit_code, 2);
  EXPECT_TRUE(contains(nothing.err, "nothing to check")) << nothing.err;
  const auto unknown = run_cli("check --preset no-such-robot");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_TRUE(contains(unknown.err, "no-such-robot")) << unknown.err;
  const auto two = run_cli("check --all --preset puma560");
  EXPECT_EQ(two.exit_code, 2);
}

// The library's one call, into registries of the caller's: everything or nothing.
TEST(PluginLibrary, LoadsIntoTheRegistriesGivenEverythingOrNothing) {
  ModelRegistry models;
  SolverRegistry solvers;
  load_plugin(kFiveBar, models, solvers);
  ASSERT_EQ(models.presets().size(), 1u);
  EXPECT_EQ(models.make_preset("five-bar-demo")->mechanism().type(), "five-bar");
  EXPECT_EQ(models.mechanisms().size(), 1u);
  EXPECT_EQ(models.sensors().size(), 1u);
  ASSERT_NE(models.export_format("five-bar", "arm-table"), nullptr);
  load_plugin(kFiveBar, models, solvers);  // again: nothing happens
  EXPECT_EQ(models.presets().size(), 1u);

  ModelRegistry builtin;
  register_builtin_models(builtin);
  const std::size_t before = builtin.presets().size();
  EXPECT_THROW(load_plugin(KINCAL_CLASH_PLUGIN, builtin, solvers), PluginError);
  EXPECT_EQ(builtin.presets().size(), before);
  try {
    load_plugin(KINCAL_WRONG_VERSION_PLUGIN, models, solvers);
    FAIL() << "loaded";
  } catch (const PluginError& e) {
    EXPECT_TRUE(contains(e.what(), "0.0.0-elsewhere")) << e.what();
    EXPECT_TRUE(contains(e.what(), plugin_abi_description())) << e.what();
  }
  load_plugin(KINCAL_SOLVER_PLUGIN, models, solvers);
  EXPECT_TRUE(solvers.contains("plugin-gn"));
}

}  // namespace
}  // namespace kincal::testing
