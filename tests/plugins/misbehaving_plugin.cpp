// A plug-in that misbehaves in every way the loader must survive with one line naming it
// (tests/cli/plugin_test.cpp, tests/cli/audit3/plugins.sh). KINCAL_TEST_PLUGIN_MODE chooses
// a misbehaviour at registration:
//   throw-int            the registration function throws 42 (not a std::exception)
//   escape-description   a preset whose description holds an ESC sequence
//   formula-preset       a preset named like a spreadsheet formula
//   formula-solver       a solver named like a spreadsheet formula
// Without it, the registration succeeds, and what misbehaves is called later:
//   preset misbehaving-formula-columns   a model whose sensor (and so its columns) is named
//                                        like a spreadsheet formula
//   preset misbehaving-throws            its factory throws 42
//   preset misbehaving-null              its factory returns null
//   preset misbehaving-nan-jacobian      puma560 with a tracker whose J_reading_pose holds NaN
//   preset misbehaving-throwing-sensor   puma560 with a tracker whose predict() throws 42
//   solver misbehaving-null-solver       its factory returns null
//   solver misbehaving-throwing-solver   its factory throws 42
// The two trackers are the sensor type misbehaving-tracker: a point tracker with a "mode".
// With KINCAL_TEST_PLUGIN_MARKER=FILE, the registration first creates FILE: a test sees whether
// the plug-in was loaded (its code ran) at all.

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <kincal/framework/extension/plugin.hpp>
#include <kincal/models/point_tracker.hpp>
#include <string>

namespace {

using namespace kincal;

// A point tracker (inner) whose Jacobian holds NaN ("nan") or whose predict throws ("throw").
class MisbehavingTracker final : public Sensor {
 public:
  MisbehavingTracker(std::shared_ptr<const Sensor> inner, std::string mode)
      : inner_(std::move(inner)), mode_(std::move(mode)) {}
  std::string type() const override { return "misbehaving-tracker"; }
  const std::string& name() const override { return inner_->name(); }
  int num_readings() const override { return inner_->num_readings(); }
  std::vector<std::string> reading_names() const override { return inner_->reading_names(); }
  std::vector<std::string> reading_units() const override { return inner_->reading_units(); }
  const std::vector<Parameter>& parameters() const override { return inner_->parameters(); }
  int position_reading_index() const override { return inner_->position_reading_index(); }
  void predict(const Eigen::Ref<const VectorXd>& params, const Pose& pose,
               Eigen::Ref<VectorXd> reading, MatrixXd* J_reading_pose,
               MatrixXd* J_reading_params) const override {
    if (mode_ == "throw") throw 42;
    inner_->predict(params, pose, reading, J_reading_pose, J_reading_params);
    if (mode_ == "nan" && J_reading_pose) (*J_reading_pose)(0, 0) = std::nan("");
  }
  const Sensor& inner() const { return *inner_; }
  const std::string& mode() const { return mode_; }

 private:
  std::shared_ptr<const Sensor> inner_;
  std::string mode_;
};

// The point-tracker type of the plug-in's own copy of kincal's registry.
const SensorType& point_tracker_type() { return ModelRegistry::global().sensor("point-tracker"); }

std::shared_ptr<const Sensor> read_tracker(const Json& j, const JsonPath& where) {
  Json inner = j;
  const std::string mode = json_field::string(json_field::member(j, "mode", where), where / "mode");
  inner.erase("mode");
  inner["type"] = "point-tracker";
  return std::make_shared<MisbehavingTracker>(point_tracker_type().read(inner, where), mode);
}

Json write_tracker(const Sensor& sensor, const Eigen::Ref<const VectorXd>& values) {
  const auto& tracker = dynamic_cast<const MisbehavingTracker&>(sensor);
  Json out = point_tracker_type().write(tracker.inner(), values);
  out["mode"] = tracker.mode();
  return out;
}

// puma560 with its tracker made misbehaving (the same parameters, so the same free mask).
std::shared_ptr<MeasurementModel> puma_with_tracker(const std::string& mode) {
  const auto puma = ModelRegistry::global().make_preset("puma560");
  auto tracker = std::make_shared<MisbehavingTracker>(puma->sensors().at(0), mode);
  auto model = std::make_shared<MeasurementModel>(
      puma->mechanism_ptr(), std::vector<std::shared_ptr<const Sensor>>{tracker});
  model->parameters() = puma->parameters();
  return model;
}

const char kFormula[] = "=cmd|' /C calc'!A0";

void register_misbehaving(ModelRegistry& models, SolverRegistry& solvers) {
  if (const char* marker = std::getenv("KINCAL_TEST_PLUGIN_MARKER"))
    std::ofstream(marker) << "the misbehaving plug-in ran\n";
  const char* mode_text = std::getenv("KINCAL_TEST_PLUGIN_MODE");
  const std::string mode = mode_text ? mode_text : "";
  const auto make_puma = [] { return ModelRegistry::global().make_preset("puma560"); };
  if (mode == "throw-int") throw 42;
  if (mode == "escape-description")
    models.add_preset({"misbehaving-escape", "clears the screen \x1b[2J\x1b[H (test)", make_puma});
  if (mode == "formula-preset") models.add_preset({kFormula, "a formula (test)", make_puma});
  if (mode == "formula-solver")
    solvers.add(kFormula, "a formula (test)", SolverKind::kLeastSquares,
                [](const std::string&) { return SolverRegistry::global().create("gn"); });
  if (!mode.empty()) return;

  models.add_sensor({"misbehaving-tracker", "a point tracker that misbehaves (test)", read_tracker,
                     write_tracker});
  models.add_preset(
      {"misbehaving-formula-columns", "puma560 with a tracker named like a formula (test)", [] {
         const auto puma = ModelRegistry::global().make_preset("puma560");
         const std::vector<std::shared_ptr<const Sensor>> sensors = {
             std::make_shared<PointTracker>(kFormula, Vector6d::Zero(), Vector3d::Zero())};
         return std::make_shared<MeasurementModel>(puma->mechanism_ptr(), sensors);
       }});
  models.add_preset({"misbehaving-throws", "a factory that throws 42 (test)",
                     []() -> std::shared_ptr<MeasurementModel> { throw 42; }});
  models.add_preset({"misbehaving-null", "a factory that returns null (test)",
                     []() -> std::shared_ptr<MeasurementModel> { return nullptr; }});
  models.add_preset({"misbehaving-nan-jacobian", "puma560 whose tracker's Jacobian is NaN (test)",
                     [] { return puma_with_tracker("nan"); }});
  models.add_preset({"misbehaving-throwing-sensor", "puma560 whose tracker throws 42 (test)",
                     [] { return puma_with_tracker("throw"); }});
  solvers.add("misbehaving-null-solver", "a factory that returns null (test)",
              SolverKind::kLeastSquares,
              [](const std::string&) -> std::unique_ptr<Solver> { return nullptr; });
  solvers.add("misbehaving-throwing-solver", "a factory that throws 42 (test)",
              SolverKind::kLeastSquares,
              [](const std::string&) -> std::unique_ptr<Solver> { throw 42; });
}

}  // namespace

KINCAL_PLUGIN(register_misbehaving)
