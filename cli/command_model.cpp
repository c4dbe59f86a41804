// kincal model: writes a built-in model, or a robot imported from its URDF, as a model file
// for users to edit.

#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"
#include "kincal/framework/base/angles.hpp"
#include "kincal/framework/base/message_excerpt.hpp"
#include "kincal/framework/io/json_input.hpp"
#include "kincal/framework/kinematics/names.hpp"
#include "kincal/models/model_io.hpp"
#include "kincal/models/point_tracker.hpp"
#include "kincal/models/pose_tracker.hpp"
#include "kincal/models/presets.hpp"
#include "kincal/models/urdf_io.hpp"

namespace kincal::cli {

namespace {

// At most a model file's size (the model file keeps the text), the reading stopping one byte
// past it, so that --urdf /dev/zero fails at once.
std::string read_text(const std::string& path) {
  try {
    return read_file_text(path, "URDF", kMaxUrdfBytes);
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--urdf ") + e.what());
  }
}

// A model of the arm in a URDF with one tracker: every parameter free (calibrate keeps the
// ones the data determine; docs/calibrating-a-serial-arm.md).
std::shared_ptr<MeasurementModel> import_model(const po::variables_map& vm) {
  if (!vm.count("tip")) throw CliError("--urdf needs --tip LINK (the link the tool is on)");
  const std::string path = vm["urdf"].as<std::string>();
  UrdfModelOptions options;
  options.sensor = vm["sensor"].as<std::string>();
  if (options.sensor != "point-tracker" && options.sensor != "pose-tracker")
    throw CliError("--sensor '" + options.sensor + "': expected point-tracker or pose-tracker");
  if (vm.count("point") && options.sensor != "point-tracker")
    throw CliError(
        "--point is the target of a point tracker; a pose tracker's marker is --target "
        "x,y,z,rx,ry,rz");
  if (vm.count("target") && options.sensor != "pose-tracker")
    throw CliError(
        "--target is a pose tracker's marker (--sensor pose-tracker); a point tracker's "
        "target is --point x,y,z");
  if (vm.count("point")) {
    const auto v = parse_numbers(vm["point"].as<std::string>(), 3, "point", "x,y,z in mm");
    options.point = Vector3d(v[0], v[1], v[2]);
  }
  // Frames as a person writes them: mm and Z-Y-X angles in degrees (the --pose rule).
  const auto frame_option = [&](const char* name) {
    const auto v =
        parse_numbers(vm[name].as<std::string>(), 6, name, "x,y,z in mm and rx,ry,rz in degrees");
    Vector6d f;
    f << v[0], v[1], v[2], v[3] * kRadiansPerDegree, v[4] * kRadiansPerDegree,
        v[5] * kRadiansPerDegree;
    return f;
  };
  if (vm.count("frame")) options.frame = frame_option("frame");
  if (vm.count("target")) options.target = frame_option("target");
  options.base_link = vm.count("base") ? vm["base"].as<std::string>() : "";
  if (vm.count("compliance")) {
    const std::string masses = vm["compliance"].as<std::string>();
    if (masses == "auto")
      options.compliance = UrdfCompliance::kAuto;
    else if (masses == "urdf")
      options.compliance = UrdfCompliance::kInertials;
    else if (masses == "fitted")
      options.compliance = UrdfCompliance::kFitted;
    else
      throw CliError("--compliance '" + masses + "': expected urdf, fitted or nothing (auto)");
  }
  options.payload_column = vm["payload-column"].as<bool>();
  if (vm.count("payload-centre")) {
    const auto v =
        parse_numbers(vm["payload-centre"].as<std::string>(), 3, "payload-centre", "x,y,z in mm");
    options.payload_centre = Vector3d(v[0], v[1], v[2]);
  }
  if ((options.payload_column || vm.count("payload-centre")) &&
      options.compliance == UrdfCompliance::kNone)
    throw CliError(std::string(options.payload_column ? "--payload-column" : "--payload-centre") +
                   " needs --compliance (a payload matters through the joints' compliance)");
  options.tip_link = vm["tip"].as<std::string>();
  const std::string text = read_text(path);
  try {
    // The file's name is recorded in the model file (JSON: UTF-8).
    return model_from_urdf(text, is_valid_utf8(path) ? path : printable(path), options);
  } catch (const UrdfError& e) {
    throw CliError(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw CliError(path + ": " + e.what());
  }
}

}  // namespace

int run_model(const Args& args) {
  po::options_description options("kincal model");
  options.add_options()("preset", po::value<std::string>()->default_value("cube-hexapod"),
                        "built-in model (kincal list models)")(
      "urdf", po::value<std::string>(),
      "import a serial arm from this URDF instead of a preset (with --tip)")(
      "tip", po::value<std::string>(), "--urdf: the link the tool or target is on")(
      "base", po::value<std::string>(), "--urdf: the base link (default: the URDF's root link)")(
      "sensor", po::value<std::string>()->default_value("point-tracker"),
      "--urdf: point-tracker (laser tracker: a point) or pose-tracker (a frame)")(
      "point", po::value<std::string>(),
      "--urdf: the point tracker's target x,y,z in the tip link's frame, mm (default 0,0,0)")(
      "frame", po::value<std::string>(),
      "--urdf: the tracker's frame in the arm's base coordinates, its starting value: "
      "x,y,z,rx,ry,rz in mm and degrees (Z-Y-X; default identity)")(
      "target", po::value<std::string>(),
      "--urdf --sensor pose-tracker: the marker's frame on the tip link, x,y,z,rx,ry,rz in mm "
      "and degrees (default identity)")(
      "compliance", po::value<std::string>()->implicit_value("auto"),
      "--urdf: joint compliance under gravity: the URDF's <inertial> masses (urdf), masses "
      "fitted as moments (fitted), or the inertials when there are any (no value)")(
      "payload-column", po::bool_switch(),
      "--compliance: the payload's mass per row, measurement column payload (kg)")(
      "payload-centre", po::value<std::string>(),
      "--compliance: the payload's centre of mass x,y,z in the tip link's frame, mm")(
      "out", po::value<std::string>()->default_value("-"), "model file to write, - for stdout");
  add_free_fix_options(options);
  po::variables_map vm;
  if (!parse_command_line("model", args, options, vm)) return 0;
  OutputPlan plan(console_output());
  if (vm.count("urdf")) plan.input("--urdf", vm["urdf"].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  std::shared_ptr<MeasurementModel> model;
  if (vm.count("urdf")) {
    if (!vm["preset"].defaulted()) throw CliError("--urdf and --preset: give one or the other");
    plan.check();
    model = import_model(vm);
  } else {
    for (const char* option :
         {"tip", "base", "point", "frame", "target", "compliance", "payload-centre"})
      if (vm.count(option)) throw CliError(std::string("--") + option + " needs --urdf");
    if (!vm["sensor"].defaulted()) throw CliError("--sensor needs --urdf");
    if (vm["payload-column"].as<bool>()) throw CliError("--payload-column needs --urdf");
    try {
      model = make_preset(vm["preset"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string("--preset: ") + e.what());
    }
    plan.check();
  }
  apply_free_fix(vm, *model);
  const std::string text =
      model_to_json(*model, model->parameters().nominal_values()).dump(2) + "\n";
  plan.write({{"--out", text}});
  return 0;
}

}  // namespace kincal::cli
