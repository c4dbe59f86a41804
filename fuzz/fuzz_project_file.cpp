// libFuzzer target: the project file reader (framework/io/project_file.hpp), as `kincal run`
// and kincal.run_project use it. Any input must either give a project or be refused with a
// ProjectError carrying one short line that names the file ("P.yaml:<line>: "); no other
// exception. A project read has steps, each with a command and options whose arguments are
// "--key" followed by its values.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "kincal/framework/io/project_file.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_project_file: %s: %s\n", what, detail.substr(0, 2000).c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  kincal::Project project;
  try {
    project = kincal::parse_project(text, "/f/P.yaml");
  } catch (const kincal::ProjectError& e) {
    const std::string what = e.what();
    if (what.rfind("/f/P.yaml:", 0) != 0) fail("message does not name the file", what);
    if (what.find('\n') != std::string::npos) fail("message is not one line", what);
    return 0;
  }
  if (project.steps.empty()) fail("a project without steps was accepted", text);
  for (std::size_t i = 0; i < project.steps.size(); ++i) {
    const kincal::ProjectStep& step = project.steps[i];
    if (step.line < 1) fail("a step without its line", text);
    for (const std::string& arg : kincal::project_step_arguments(step))
      if (arg.empty() && step.options.empty()) fail("an argument without an option", text);
    (void)kincal::project_step_location(project, i);
    (void)kincal::project_record(project, i).dump();
  }
  return 0;
}
