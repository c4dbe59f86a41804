// The CLI works for every registered model: `list`, `simulate --preset`, `model --preset`,
// `fk --actuators` and `ik` on whatever `kincal list models` shows, with no test edit when a
// preset is added.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"
#include "kincal/framework/extension/model_registry.hpp"
#include "kincal/framework/kinematics/units.hpp"
#include "kincal/models/model_io.hpp"

namespace kincal {
namespace {

using kincal::testing::read_text;
using kincal::testing::run_cli;
using kincal::testing::TempDir;
using Json = nlohmann::json;

// Names on the lines of `kincal list <what>`: the first word of each line.
std::vector<std::string> listed(const std::string& what) {
  const auto result = run_cli("list " + what);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  std::vector<std::string> names;
  std::istringstream in(result.out);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) names.push_back(line.substr(0, line.find(' ')));
  return names;
}

TEST(CliModels, ListShowsEveryRegisteredPresetMechanismAndSensor) {
  const auto models = listed("models");
  std::vector<std::string> presets;
  for (const auto& p : ModelRegistry::global().presets()) presets.push_back(p.name);
  EXPECT_EQ(models, presets);
  std::vector<std::string> sensors;
  for (const auto& s : ModelRegistry::global().sensors()) sensors.push_back(s.type);
  EXPECT_EQ(listed("sensors"), sensors);
  std::vector<std::string> mechanisms;
  for (const auto& m : ModelRegistry::global().mechanisms()) mechanisms.push_back(m.type);
  EXPECT_EQ(listed("mechanisms"), mechanisms);
  // Without an argument: every section under its heading.
  const auto all = run_cli("list");
  EXPECT_EQ(all.exit_code, 0) << all.err;
  for (const char* heading : {"solvers:", "models:", "mechanisms:", "sensors:"})
    EXPECT_NE(all.out.find(heading), std::string::npos) << heading;
  const auto bad = run_cli("list robots");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("cannot list 'robots'"), std::string::npos) << bad.err;
}

// The acceptance check: every preset, noise-free, seeds 1-5, converged with every
// free parameter within 1e-6 (of its unit) of the truth.
TEST(CliModels, EveryPresetIsRecoveredExactlyWithoutNoise) {
  for (const auto& preset : listed("models")) {
    for (int seed = 1; seed <= 5; ++seed) {
      const auto run = run_cli("simulate --preset " + preset + " --noise-half-width 0 --seed " +
                               std::to_string(seed) + " --validation 20 --json -");
      ASSERT_EQ(run.exit_code, 0) << preset << " seed " << seed << ": " << run.err;
      const Json j = Json::parse(run.out);
      EXPECT_EQ(j["termination"], "converged")
          << preset << " seed " << seed << ": " << j["message"];
      EXPECT_EQ(j["scenario"]["model"], preset);
      for (const auto& p : j["parameters"]) {
        double d = p["estimate"].get<double>() - p["true"].get<double>();
        if (p["unit"] == "rad") d = std::remainder(d, 2 * M_PI);
        EXPECT_LT(std::abs(d), 1e-6)
            << preset << " seed " << seed << ": " << p["name"] << " " << p["unit"];
        EXPECT_TRUE(is_known_unit(p["unit"].get<std::string>())) << p["unit"];
      }
    }
  }
}

TEST(CliModels, EveryPresetWritesAModelThatFkAndIkUse) {
  TempDir dir("cli-models");
  for (const auto& preset : listed("models")) {
    const std::string m = dir / (preset + ".json");
    ASSERT_EQ(run_cli("model --preset " + preset + " --out " + m).exit_code, 0) << preset;
    const auto model = ModelRegistry::global().make_preset(preset);
    // ik at the home pose, then fk of those actuator values: back home.
    const Pose& home = model->mechanism().home_pose();
    const Vector3d zyx = euler_zyx(home.rotation) * (180 / M_PI);
    std::ostringstream pose;
    pose.precision(17);
    pose << home.translation.x() << "," << home.translation.y() << "," << home.translation.z()
         << "," << zyx[2] << "," << zyx[1] << "," << zyx[0];
    const auto ik = run_cli("ik --model " + m + " --pose=" + pose.str());
    ASSERT_EQ(ik.exit_code, 0) << preset << ": " << ik.err;
    std::istringstream in(ik.out);
    std::string name, actuators;
    double value;
    for (int i = 0; i < model->mechanism().num_actuators() && in >> name >> value; ++i) {
      std::ostringstream v;
      v.precision(17);
      v << value;
      actuators += (i ? "," : "") + v.str();
    }
    const auto fk = run_cli("fk --model " + m + " --actuators=" + actuators);
    ASSERT_EQ(fk.exit_code, 0) << preset << ": " << fk.err;
    std::istringstream out(fk.out);
    double x, y, z;
    out >> name >> x >> y >> z;
    EXPECT_NEAR(x, home.translation.x(), 1e-5) << preset;
    EXPECT_NEAR(y, home.translation.y(), 1e-5) << preset;
    EXPECT_NEAR(z, home.translation.z(), 1e-5) << preset;
  }
}

TEST(CliModels, UnreachablePosesAndBadUnitsAreClearErrors) {
  TempDir dir("cli-models-errors");
  const std::string m = dir / "M.json";
  ASSERT_EQ(run_cli("model --out " + m).exit_code, 0);
  const auto inf = run_cli("ik --model " + m + " --pose=1e308,1e308,1e308,0,0,0");
  EXPECT_EQ(inf.exit_code, 2);
  EXPECT_NE(inf.err.find("inverse kinematics"), std::string::npos) << inf.err;
  EXPECT_EQ(inf.out, "");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate --param-error 5furlongs", "--param-error '5furlongs': '5furlongs': unknown unit"},
      {"simulate --noise-half-width 1mm,2mm",
       "--noise-half-width '1mm,2mm': '1mm,2mm' gives a value in mm twice"},
      {"simulate --config-range=-3mm", "--config-range '-3mm': expected values >= 0"},
      {"simulate --preset no-such-robot", "--preset: unknown model preset 'no-such-robot'"},
      {"simulate --preset cube-hexapod --model " + m, "give either --preset NAME or --model FILE"},
      {"fk --model " + m + " --actuators 1,2,3",
       "--actuators '1,2,3': 3 numbers, expected 6 (leg1 (mm),leg2 (mm)"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST(CliModels, ParameterErrorsAndRangesFollowTheirUnits) {
  // A bare number is mm; the cube hexapod has no angle parameters, so rad values change
  // nothing; ranges come from the model unless given.
  const auto plain = Json::parse(run_cli("simulate --case 3 --seed 7 --json -").out);
  const auto units = Json::parse(
      run_cli("simulate --case 3 --seed 7 --param-error 5mm,0.02rad --config-range 20mm --json -")
          .out);
  EXPECT_EQ(plain["parameters"], units["parameters"]);
  EXPECT_EQ(plain["scenario"]["config_range_mm"], 20.0);
  EXPECT_EQ(plain["scenario"]["actuator_ranges"]["leg6"], 20.0);
  EXPECT_EQ(units["scenario"]["param_error_half_width_rad"], 0.02);
  const auto wider =
      Json::parse(run_cli("simulate --case 3 --seed 7 --config-range 10 --json -").out);
  EXPECT_EQ(wider["scenario"]["actuator_ranges"]["leg1"], 10.0);
}

}  // namespace
}  // namespace kincal

namespace kincal {
namespace {

// The acceptance check for serial arms: calibrated from files (a model file and a
// CSV of tracker readings, some missing), the estimate lies within its reported standard
// deviations of the simulated truth.
TEST(CliModels, SerialArmFromFilesWithMissingTrackerReadingsRecoversTheTruth) {
  TempDir dir("cli-arm-files");
  const std::string nominal = dir / "nominal.json", data = dir / "D.csv", report = dir / "R.json";
  ASSERT_EQ(run_cli("model --preset puma560 --out " + nominal).exit_code, 0);
  const auto sim = run_cli(
      "simulate --model " + nominal +
      " --poses 40 --noise-half-width 0.02mm --seed 11 --validation 10 --write-data " + data);
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  // The target was out of the tracker's sight in every fifth configuration: empty fields.
  std::istringstream in(read_text(data));
  std::ostringstream out;
  std::string line;
  int row = 0, blanked = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#' && line.rfind("joint1", 0) != 0 && row++ % 5 == 0) {
      for (int i = 0; i < 3; ++i) line = line.substr(0, line.rfind(','));
      line += ",,,";
      ++blanked;
    }
    out << line << "\n";
  }
  ASSERT_EQ(blanked, 8);
  std::ofstream(data) << out.str();

  const auto cal =
      run_cli("calibrate --model " + nominal + " --data " + data + " --json " + report);
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  const Json r = Json::parse(read_text(report));
  EXPECT_EQ(r["termination"], "converged");
  EXPECT_EQ(r["readings_per_sensor"]["tracker"], 32);
  EXPECT_EQ(r["readings"], 96);
  const Json truth_file = Json::parse(read_text(dir / "D.truth.json"));
  const auto truth = model_from_json(truth_file, "D.truth.json");
  int within_3 = 0, count = 0;
  for (const auto& p : r["parameters"]) {
    const int i = truth->parameters().index_of(p["name"]);
    double d = p["estimate"].get<double>() - truth->parameters()[i].nominal;
    if (p["unit"] == "rad") d = std::remainder(d, 2 * M_PI);
    const double z = std::abs(d) / p["std"].get<double>();
    EXPECT_LT(z, 4.0) << p["name"] << ": " << d << " " << p["unit"] << " off, std " << p["std"];
    within_3 += z < 3;
    ++count;
  }
  EXPECT_EQ(count, 27);
  EXPECT_GE(within_3, 26);  // 3 sigma covers 99.7 %: at most one of 27 outside
}

}  // namespace
}  // namespace kincal
