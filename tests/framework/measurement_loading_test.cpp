// The library's entry from a measurement file to screened rows (measurement_loading.hpp):
// notes come back as data, in order, and nothing is printed; a refusal is one exception that
// names the file and line; copied rows count once.

#include "kincal/framework/calibration/measurement_loading.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "kincal/framework/calibration/simulation.hpp"
#include "kincal/models/presets.hpp"

namespace kincal {
namespace {

class MeasurementLoading : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = make_cube_hexapod();
    ScenarioOptions options;
    options.num_configurations = 30;
    options.noise_half_width.set(kincal::kMillimetre, 0.01);
    options.num_validation = 0;
    options.seed = 4;
    const Scenario s = make_scenario(model_, options);
    nominal_ = model_->parameters().nominal_values();
    // Rows 2-31: the scenario; then a copy of the first row, and a row no leg lengths reach.
    std::string csv = measurements_to_csv(s.calibration, actuator_names(), {"gauge"}, "");
    const std::string header = csv.substr(0, csv.find('\n') + 1);
    const std::string first =
        csv.substr(header.size(), csv.find('\n', header.size()) + 1 - header.size());
    csv += first + "-354,354,354,354,354,382,300\n";
    // An extra column the reader ignores, with a notice.
    std::string with_extra;
    std::istringstream in(csv);
    for (std::string line; std::getline(in, line);)
      with_extra +=
          line + (line == header.substr(0, header.size() - 1) ? ",temperature" : ",21") + "\n";
    path_ = (std::filesystem::temp_directory_path() /
             ("kincal-loading-" + std::to_string(::getpid()) + ".csv"))
                .string();
    std::ofstream(path_) << with_extra;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  std::vector<std::string> actuator_names() const {
    std::vector<std::string> names;
    for (const auto& a : model_->mechanism().actuators()) names.push_back(a.name);
    return names;
  }
  std::shared_ptr<MeasurementModel> model_;
  VectorXd nominal_;
  std::string path_;
};

TEST_F(MeasurementLoading, NotesComeBackInOrderAndCopiesCountOnce) {
  MeasurementLoadOptions options;
  options.skip_unreachable_rows = true;
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  const LoadedMeasurements loaded = load_measurements(path_, *model_, nominal_, options);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_EQ(loaded.data.size(), 30);
  EXPECT_EQ(loaded.lines.front(), 2);
  EXPECT_EQ(loaded.lines.back(), 31);
  EXPECT_EQ(loaded.skipped_lines, std::vector<int>{33});
  EXPECT_EQ(loaded.duplicate_rows, 1);
  EXPECT_NE(loaded.copied_rows_note.find("line(s) 32 (= line 2)"), std::string::npos)
      << loaded.copied_rows_note;
  ASSERT_EQ(loaded.notes.size(), 2u);
  EXPECT_NE(loaded.notes[0].find("ignoring column 'temperature'"), std::string::npos);
  EXPECT_NE(loaded.notes[1].find(":33: skipped, forward kinematics"), std::string::npos)
      << loaded.notes[1];
}

TEST_F(MeasurementLoading, AnUnreachableRowIsOneExceptionNamingItsLine) {
  std::string what = "(no error)";
  try {
    load_measurements(path_, *model_, nominal_);
  } catch (const std::invalid_argument& e) {
    what = e.what();
  }
  EXPECT_EQ(what.rfind(path_ + ": forward kinematics of the model fails at line 33 (", 0), 0u)
      << what;
  // Refused before the notes would matter: the caller has nothing to print but the refusal.
  EXPECT_THROW(load_measurements(path_ + ".missing", *model_, nominal_), std::invalid_argument);
}

}  // namespace
}  // namespace kincal
