// libFuzzer target: the model reader (framework/io/json_input.hpp + models/model_io.hpp), as
// load_model uses them. Any input must either give a model or be refused with
// std::invalid_argument carrying one short line (no other exception: model_from_json checks
// types before reading them). A model read must write and read back to the same model: the
// same names, free mask and values bit for bit, and the same home pose (its rotation goes
// through Euler angles in degrees, so it is compared to 1e-9).

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "kincal/framework/io/json_input.hpp"
#include "kincal/models/model_io.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_model_file: %s: %s\n", what, detail.substr(0, 2000).c_str());
  std::abort();
}

void check_message(const std::string& what) {
  if (what.rfind("M.json: ", 0) != 0) fail("message does not name the file", what);
  if (what.find('\n') != std::string::npos) fail("message is not one line", what);
  if (what.size() > 600) fail("message too long", what);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::shared_ptr<kincal::MeasurementModel> model;
  try {
    model = kincal::model_from_json(kincal::parse_json_text(text, "M.json"), "M.json");
  } catch (const std::invalid_argument& e) {
    check_message(e.what());
    return 0;
  }
  // Round trip: written, read back, written again.
  const kincal::VectorXd values = model->parameters().nominal_values();
  const std::string written = kincal::model_to_json(*model, values).dump(2);
  std::shared_ptr<kincal::MeasurementModel> back;
  try {
    back = kincal::model_from_json(kincal::parse_json_text(written, "M.json"), "M.json");
  } catch (const std::invalid_argument& e) {
    fail("a written model does not read back", std::string(e.what()) + "\n" + written);
  }
  if (back->parameters().names() != model->parameters().names()) fail("names changed", written);
  if (back->parameters().free_indices() != model->parameters().free_indices())
    fail("free mask changed", written);
  const kincal::VectorXd back_values = back->parameters().nominal_values();
  for (int i = 0; i < values.size(); ++i)
    if (!(back_values[i] == values[i]) && !(values[i] == 0 && back_values[i] == 0))
      fail("a value changed", model->parameters()[i].name + "\n" + written);
  const kincal::Pose& a = model->mechanism().home_pose();
  const kincal::Pose& b = back->mechanism().home_pose();
  if (!(a.translation == b.translation)) fail("home position changed", written);
  if (!((a.rotation - b.rotation).norm() <= 1e-9))
    fail("home rotation changed", written + "\nfrom\n" + text);
  return 0;
}
