// kincal.detect: images of a calibration target in, a camera's measurement file out, and a
// starting model (vision/detect.hpp), called from Python as the program calls it. Built when
// the library's vision part is (OpenCV installed); otherwise the call says what to install.
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "interrupt.hpp"
#include "kincal/framework/io/output_plan.hpp"
#include "model_handle.hpp"

#if KINCAL_WITH_VISION
#include "kincal/vision/detect.hpp"
#endif

namespace kincal::python {

namespace {

#if KINCAL_WITH_VISION

py::dict detect_workflow(const std::string& target, const std::string& poses,
                         const std::string& images, const std::string& out,
                         const std::string& camera, double gate_px, const std::string& start_model,
                         const std::string& mounting, const std::optional<ModelHandle>& mechanism,
                         const std::vector<double>& intrinsics, const std::string& json,
                         bool catch_sigint) {
  vision::DetectRequest request;
  request.target = vision::TargetSpec::parse(target);
  request.camera_name = camera;
  if (!(gate_px > 0)) throw std::invalid_argument("gate_px must be positive");
  request.options.max_homography_rms_px = gate_px;
  if (poses.empty() && images.empty())
    throw std::invalid_argument("give poses (images with the robot's poses) or images (a folder)");
  if (mounting != "eye-to-hand" && mounting != "eye-in-hand")
    throw std::invalid_argument("mounting '" + mounting + "': expected eye-to-hand or eye-in-hand");
  if (!intrinsics.empty() && intrinsics.size() != 4)
    throw std::invalid_argument("intrinsics: expected (fx, fy, cx, cy) in px");
  if (start_model.empty() && (mechanism || !intrinsics.empty()))
    throw std::invalid_argument("mechanism and intrinsics are for start_model");
  request.images =
      poses.empty() ? vision::images_in_folder(images) : vision::read_image_poses(poses, images);
  OutputPlan plan(python_output());
  if (!poses.empty()) plan.input("poses", poses);
  for (const auto& path : request.images.paths) plan.input("an image", path);
  plan.output("out", out);
  if (!start_model.empty()) plan.output("start_model", start_model);
  if (!json.empty()) plan.output("json", json);
  plan.check();

  vision::DetectResult result;
  {
    py::gil_scoped_release release;
    SigintScope sigint(catch_sigint);
    request.stop_requested = [] { return sigint_received(); };
    result = vision::detect_images(request);
  }
  std::optional<vision::StartRequest> start;
  if (!start_model.empty()) {
    start = vision::StartRequest{};
    start->mounting =
        mounting == "eye-in-hand" ? CameraMounting::kEyeInHand : CameraMounting::kEyeToHand;
    if (mechanism) start->mechanism = mechanism->model->mechanism_ptr();
    if (!intrinsics.empty()) {
      CameraIntrinsics in;
      in.fx = intrinsics[0];
      in.fy = intrinsics[1];
      in.cx = intrinsics[2];
      in.cy = intrinsics[3];
      start->intrinsics = in;
    }
  }
  const vision::DetectOutputs outputs = vision::detect_outputs(request, result, start);
  std::vector<std::pair<std::string, std::string>> files;
  if (!outputs.csv.empty()) files.emplace_back("out", outputs.csv);
  if (!outputs.model_text.empty()) files.emplace_back("start_model", outputs.model_text);
  if (!json.empty()) files.emplace_back("json", outputs.json.dump(2) + "\n");
  {
    py::gil_scoped_release release;
    if (result.found() > 0) {
      plan.write(files);
    } else if (!json.empty()) {
      plan.write({files.back()});
    }
  }
  py::dict answer;
  answer["report"] = outputs.json.dump();
  answer["text"] = result.text() + outputs.start_text;
  answer["csv"] = outputs.csv;
  answer["start_error"] = outputs.start_error;
  answer["interrupted"] = result.interrupted;
  return answer;
}

#else

py::dict detect_workflow(const std::string&, const std::string&, const std::string&,
                         const std::string&, const std::string&, double, const std::string&,
                         const std::string&, const std::optional<ModelHandle>&,
                         const std::vector<double>&, const std::string&, bool) {
  throw std::invalid_argument(
      "kincal.detect needs OpenCV, and this kincal was built without it: install Debian's "
      "libopencv-dev and libopencv-contrib-dev, then rebuild");
}

#endif

}  // namespace

void bind_vision(py::module_& m) {
  m.def("_detect", &detect_workflow, py::arg("target"), py::arg("poses"), py::arg("images"),
        py::arg("out"), py::arg("camera"), py::arg("gate_px"), py::arg("start_model"),
        py::arg("mounting"), py::arg("mechanism"), py::arg("intrinsics"), py::arg("json"),
        py::arg("catch_sigint"),
        "Targets found in images (kincal.detect is its face): writes `out` (and `start_model`, "
        "`json` when given) and returns the report, the text and the table.");
}

}  // namespace kincal::python
