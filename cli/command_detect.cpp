// kincal detect: images of a calibration target in, a measurement file out (vision/detect.hpp),
// and, with --start-model, a model file whose camera and mounts start where the images say.

#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/model_args.hpp"

#if KINCAL_WITH_VISION
#include "kincal/cli/interrupt.hpp"
#include "kincal/cli/progress.hpp"
#include "kincal/vision/detect.hpp"
#endif

namespace kincal::cli {

#if KINCAL_WITH_VISION

namespace {

CameraMounting parse_mounting(const std::string& text) {
  if (text == "eye-to-hand") return CameraMounting::kEyeToHand;
  if (text == "eye-in-hand") return CameraMounting::kEyeInHand;
  throw CliError("--mounting '" + text + "': expected eye-to-hand or eye-in-hand");
}

// "2px" or "2": the gate in px.
double parse_pixels(const std::string& text, const std::string& option) {
  std::string number = text;
  if (number.size() > 2 && number.compare(number.size() - 2, 2, "px") == 0)
    number.erase(number.size() - 2);
  const std::vector<double> values = parse_numbers(number, 1, option, "a distance in px, e.g. 2px");
  if (!(values[0] > 0)) throw CliError("--" + option + " '" + text + "': expected a positive px");
  return values[0];
}

}  // namespace

int run_detect(const Args& args) {
  po::options_description options("kincal detect");
  options.add_options()(
      "target", po::value<std::string>(),
      "the target: chessboard:ROWSxCOLS:SPACING (inner corners), circle-grid:ROWSxCOLS:SPACING, "
      "modified-circle-grid:ROWSxCOLS:SPACING (one larger dot at the origin) or "
      "charuco:ROWSxCOLS:SQUARE:MARKER:DICTIONARY (squares; DICT_6X6_250...); lengths with "
      "their unit (25.4mm, 0.036m)")(
      "poses", po::value<std::string>(),
      "CSV: a column 'image' (the image file, relative to this file's folder or to --images) "
      "and the configuration's columns as a measurement file names them (joint1_deg, "
      "flange.x_m, ...), copied to --out")(
      "images", po::value<std::string>(),
      "the folder of the images (without --poses: every image file in it, in natural order)")(
      "out", po::value<std::string>(),
      "the measurement file to write (CSV), - for standard output")(
      "camera", po::value<std::string>()->default_value("camera"),
      "the camera's name (its readings are <camera>.p<i>.u and .v, px)")(
      "gate", po::value<std::string>()->default_value("2px"),
      "reject a detection whose points are further than this (RMS, px) from the homography fitted "
      "to them")(
      "start-model", po::value<std::string>(),
      "also write a model file to start calibrate from: the camera's intrinsics (OpenCV's "
      "calibrateCamera, or --intrinsics) and both mounts from the closed-form hand-eye solution")(
      "mounting", po::value<std::string>()->default_value("eye-to-hand"),
      "with --start-model: eye-to-hand (the camera fixed, the target on the robot) or eye-in-hand")(
      "mechanism", po::value<std::string>(),
      "with --start-model: a model file whose mechanism the pose columns configure (default: "
      "flange-pose, columns flange.x, .y, .z, .rotvec_x, _y, _z)")(
      "intrinsics", po::value<std::string>(),
      "with --start-model: fx,fy,cx,cy in px instead of OpenCV's calibration");
  add_json_option(options, "what became of each image");
  add_progress_option(options);
  po::variables_map vm;
  if (!parse_command_line("detect", args, options, vm)) return 0;

  if (!vm.count("target")) throw CliError("--target is required (e.g. chessboard:6x8:20mm)");
  if (!vm.count("out")) throw CliError("--out FILE.csv is required");
  if (!vm.count("poses") && !vm.count("images"))
    throw CliError("give --poses FILE (images with the robot's poses) or --images FOLDER");
  for (const char* start_option : {"mechanism", "intrinsics"})
    if (vm.count(start_option) && !vm.count("start-model"))
      throw CliError(std::string("--") + start_option + " is for --start-model");

  vision::DetectRequest request;
  try {
    request.target = vision::TargetSpec::parse(vm["target"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--target: ") + e.what());
  }
  request.camera_name = vm["camera"].as<std::string>();
  request.options.max_homography_rms_px = parse_pixels(vm["gate"].as<std::string>(), "gate");
  const CameraMounting mounting = parse_mounting(vm["mounting"].as<std::string>());
  std::optional<CameraIntrinsics> intrinsics;
  if (vm.count("intrinsics")) {
    const auto v =
        parse_numbers(vm["intrinsics"].as<std::string>(), 4, "intrinsics", "fx,fy,cx,cy in px");
    CameraIntrinsics in;
    in.fx = v[0];
    in.fy = v[1];
    in.cx = v[2];
    in.cy = v[3];
    if (!(in.fx > 0 && in.fy > 0)) throw CliError("--intrinsics: fx and fy must be positive");
    intrinsics = in;
  }

  OutputPlan plan(console_output());
  const std::string images_folder = vm.count("images") ? vm["images"].as<std::string>() : "";
  if (vm.count("poses")) plan.input("--poses", vm["poses"].as<std::string>());
  if (vm.count("mechanism")) plan.input("--mechanism", vm["mechanism"].as<std::string>());
  plan.output("--out", vm["out"].as<std::string>());
  if (vm.count("start-model")) plan.output("--start-model", vm["start-model"].as<std::string>());
  const std::string json_file = json_output(vm);
  if (!json_file.empty()) plan.output("--json", json_file);
  request.images = vm.count("poses")
                       ? vision::read_image_poses(vm["poses"].as<std::string>(), images_folder)
                       : vision::images_in_folder(images_folder);
  for (const auto& path : request.images.paths) plan.input("an image", path);
  plan.check();
  std::shared_ptr<const Mechanism> mechanism;
  if (vm.count("mechanism"))
    mechanism = load_model_file(vm["mechanism"].as<std::string>())->mechanism_ptr();

  vision::DetectResult result;
  {
    InterruptGuard guard("detect");
    Progress progress("detect", static_cast<long>(request.images.paths.size()), "images",
                      progress_wanted(vm));
    request.on_image = [&progress](int) { progress.advance(); };
    request.stop_requested = [] { return interrupt_requested(); };
    result = vision::detect_images(request);
    progress.finish();
  }
  std::optional<vision::StartRequest> start;
  if (vm.count("start-model")) start = vision::StartRequest{mounting, mechanism, intrinsics};
  const vision::DetectOutputs outputs = vision::detect_outputs(request, result, start);
  std::vector<std::pair<std::string, std::string>> files;
  if (!outputs.csv.empty()) files.emplace_back("--out", outputs.csv);
  if (!outputs.model_text.empty()) files.emplace_back("--start-model", outputs.model_text);
  if (!outputs.start_error.empty())
    err() << "kincal detect: no starting model: " << outputs.start_error << "\n";
  if (!json_file.empty()) files.emplace_back("--json", outputs.json.dump(2) + "\n");
  if (!plan.to_stdout("--out") && (json_file.empty() || !plan.to_stdout("--json")))
    out() << result.text() << outputs.start_text;
  if (result.found() == 0) {
    if (!json_file.empty()) plan.write({files.back()});
    err() << "kincal detect: the target was found in none of the " << result.records.size()
          << " images looked at; nothing written to --out\n";
    return 1;
  }
  plan.write(files);
  if (result.interrupted) {
    err() << "kincal detect: interrupted: wrote the " << result.found() << " images found among "
          << "the first " << result.records.size() << " of " << result.total
          << (vm.count("start-model") ? " (no starting model from part of the images)" : "")
          << "\n";
    return 130;
  }
  // The table is written (detection worked), but what was asked for is not all there.
  return outputs.start_error.empty() ? 0 : 1;
}

#else

int run_detect(const Args& args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    out() << "kincal detect: find a calibration target's points in images (needs OpenCV)\n";
    return 0;
  }
  throw CliError(
      "kincal detect needs OpenCV, and this kincal was built without it: install Debian's "
      "libopencv-dev and libopencv-contrib-dev, then rebuild (scripts/setup.sh "
      "-DKINCAL_WITH_OPENCV=ON)");
}

#endif

}  // namespace kincal::cli
