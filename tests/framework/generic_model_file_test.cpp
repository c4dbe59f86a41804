// The generic model-file reader and writer (framework/extension/generic_model_file.hpp): keys from
// the parameter names, values in their units (angles in degrees), options, and bad input as one
// line naming the key and where it is. The built-in sensors that use it keep their files
// byte for byte: model_conformance_test.cpp (round trip of every preset) and
// model_io_test.cpp (the files in examples/) check that.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "kincal/framework/extension/generic_model_file.hpp"

namespace kincal {
namespace {

// A sensor with one of each parameter form and an option: base.{x,y,z} (mm), tilt (rad),
// gain (mm), frame.{x,y,z,rx,ry,rz} (mm, rad); option max_range.
class SampleSensor final : public Sensor {
 public:
  SampleSensor(std::string name, const VectorXd& v, double max_range)
      : name_(std::move(name)), max_range_(max_range) {
    const char* names[11] = {"base.x",  "base.y",  "base.z",   "tilt",     "gain",    "frame.x",
                             "frame.y", "frame.z", "frame.rx", "frame.ry", "frame.rz"};
    const char* units[11] = {"mm", "mm", "mm", "rad", "mm", "mm", "mm", "mm", "rad", "rad", "rad"};
    for (int i = 0; i < 11; ++i)
      parameters_.push_back({name_ + "." + names[i], v.size() ? v[i] : 0.0, units[i], false});
  }
  std::string type() const override { return "sample"; }
  const std::string& name() const override { return name_; }
  int num_readings() const override { return 1; }
  std::vector<std::string> reading_units() const override { return {"mm"}; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  void predict(const Eigen::Ref<const VectorXd>& params, const Pose&, Eigen::Ref<VectorXd> reading,
               MatrixXd*, MatrixXd*) const override {
    reading[0] = params.sum();
  }
  double max_range() const { return max_range_; }

 private:
  std::string name_;
  double max_range_;
  std::vector<Parameter> parameters_;
};

SensorType sample_type() {
  VectorXd defaults = VectorXd::Zero(11);
  defaults[4] = 1.5;  // gain, optional
  return generic_sensor_type(
      "sample", "a test sensor",
      sensor_layout(SampleSensor("s", defaults, 0), {"gain"}, {{"max_range", 1000}}),
      [](const std::string& name, const VectorXd& v, const ModelFileOptions& o) {
        return std::make_shared<SampleSensor>(name, v, o.at("max_range"));
      },
      [](const Sensor& s) {
        return ModelFileOptions{{"max_range", static_cast<const SampleSensor&>(s).max_range()}};
      });
}

const char* kSample = R"({"type": "sample", "name": "probe", "base": [1, 2, 3], "tilt_deg": 30,
  "gain": 2.5, "frame": {"position": [4, 5, 6], "rotation_zyx_deg": [10, 20, 30]},
  "max_range": 500})";

std::string read_error(const std::string& text) {
  try {
    sample_type().read(Json::parse(text), JsonPath("model.json", "sensors[0]"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GenericModelFile, ReadsEveryParameterFormInItsUnit) {
  const auto sensor = sample_type().read(Json::parse(kSample), JsonPath("model.json"));
  ASSERT_EQ(sensor->num_parameters(), 11);
  const auto& p = sensor->parameters();
  EXPECT_EQ(p[0].name, "probe.base.x");
  EXPECT_EQ(p[2].nominal, 3);
  EXPECT_NEAR(p[3].nominal, M_PI / 6, 1e-15);  // tilt_deg 30
  EXPECT_EQ(p[4].nominal, 2.5);
  EXPECT_EQ(p[7].nominal, 6);
  EXPECT_NEAR(p[10].nominal, M_PI / 6, 1e-15);  // rz 30 degrees
  EXPECT_EQ(static_cast<const SampleSensor&>(*sensor).max_range(), 500);
}

TEST(GenericModelFile, WritesWhatItReadsInParameterOrder) {
  const SensorType type = sample_type();
  const auto sensor = type.read(Json::parse(kSample), JsonPath("model.json"));
  VectorXd values(11);
  for (int i = 0; i < 11; ++i) values[i] = sensor->parameters()[i].nominal;
  const Json written = type.write(*sensor, values);
  std::vector<std::string> keys;
  for (const auto& item : written.items()) keys.push_back(item.key());
  EXPECT_EQ(keys,
            (std::vector<std::string>{"name", "base", "tilt_deg", "gain", "frame", "max_range"}));
  EXPECT_EQ(written["base"].dump(), "[1.0,2.0,3.0]");
  EXPECT_NEAR(written["tilt_deg"].get<double>(), 30, 1e-12);
  EXPECT_EQ(written["frame"]["position"].dump(), "[4.0,5.0,6.0]");
  EXPECT_EQ(written["max_range"], 500.0);
  Json again = written;
  again["type"] = "sample";
  const auto back = type.read(again, JsonPath("model.json"));
  EXPECT_EQ(type.write(*back, values).dump(), written.dump());
}

TEST(GenericModelFile, AnOptionalKeyTakesTheNominalValueAndAnOptionItsDefault) {
  const auto sensor = sample_type().read(
      Json::parse(R"({"type": "sample", "name": "p", "base": [0, 0, 0], "tilt_deg": 0,
                      "frame": {"position": [0, 0, 0], "rotation_zyx_deg": [0, 0, 0]}})"),
      JsonPath("model.json"));
  EXPECT_EQ(sensor->parameters()[4].nominal, 1.5);
  EXPECT_EQ(static_cast<const SampleSensor&>(*sensor).max_range(), 1000);
}

TEST(GenericModelFile, BadInputIsOneLineNamingTheKeyAndWhere) {
  std::string text = kSample;
  EXPECT_EQ(read_error(R"({"type": "sample", "name": "p", "tilt_deg": 0})"),
            "model.json: sensors[0]: missing key 'base'");
  EXPECT_EQ(read_error(R"({"type": "sample", "name": "p", "bse": [0, 0, 0]})"),
            "model.json: sensors[0]: unknown key 'bse' (expected base, frame, gain, max_range, "
            "name, tilt_deg, type)");
  text.replace(text.find("[1, 2, 3]"), 9, "[1, 2]");
  const std::string short_base = read_error(text);
  EXPECT_EQ(short_base.rfind("model.json: sensors[0].base: ", 0), 0u) << short_base;
  text = kSample;
  text.replace(text.find("30,"), 2, "\"x\"");
  const std::string tilt = read_error(text);
  EXPECT_EQ(tilt.rfind("model.json: sensors[0].tilt_deg: ", 0), 0u) << tilt;
  text = kSample;
  text.replace(text.find("500"), 3, "\"far\"");
  const std::string option = read_error(text);
  EXPECT_EQ(option.rfind("model.json: sensors[0].max_range: ", 0), 0u) << option;
  EXPECT_EQ(std::count(option.begin(), option.end(), '\n'), 0);
}

TEST(GenericModelFile, ATypeWhoseParametersHaveNoFileFormIsRefused) {
  ModelFileLayout layout;
  layout.parameters = {{"leg.a", 0, "mm", false}, {"leg.b", 0, "mm", false}};
  auto make = [](const std::string&, const VectorXd&, const ModelFileOptions&) {
    return std::shared_ptr<const Sensor>();
  };
  EXPECT_THROW(generic_sensor_type("odd", "", layout, make), std::logic_error);
  layout.parameters = {{"gain", 0, "mm", false}};
  layout.optional_keys = {"gian"};
  EXPECT_THROW(generic_sensor_type("odd", "", layout, make), std::logic_error);
}

TEST(GenericModelFile, AMechanismReadsTheSameWay) {
  ModelFileLayout layout;
  layout.parameters = {{"offset", 0, "mm", false}};
  bool made = false;
  const MechanismType type =
      generic_mechanism_type("m", "", layout, [&](const VectorXd& v, const ModelFileOptions&) {
        made = v[0] == 4;
        return std::shared_ptr<const Mechanism>();
      });
  // A null mechanism is the type's bug (std::logic_error), found after make() ran.
  EXPECT_THROW(type.read(Json::parse(R"({"type": "m", "offset": 4})"), JsonPath("f")),
               std::logic_error);
  EXPECT_TRUE(made);
  EXPECT_THROW(type.read(Json::parse(R"({"type": "m", "ofset": 4})"), JsonPath("f")),
               std::invalid_argument);
}

}  // namespace
}  // namespace kincal
