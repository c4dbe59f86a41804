#pragma once
// One function per sub-command, each in its own cli/command_<name>.cpp. A command receives
// the arguments after its name, prints to its standard output (out(), console.hpp), and
// returns the exit code. Bad input is thrown as std::exception (usually CliError) and run()
// (cli/run.cpp) turns it into one line on its standard error (err()) and exit code 2. Every file a
// command reads or writes goes through an OutputPlan (framework/io/output_plan.hpp), whose
// OutputError is bad input too.

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace kincal::cli {

class CliError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Args = std::vector<std::string>;

struct Command {
  const char* name;
  const char* summary;
  std::function<int(const Args&)> run;
};

/// The command table, in the order `kincal --help` lists them (cli/run.cpp).
const std::vector<Command>& commands();

int run_list(const Args& args);
int run_simulate(const Args& args);
int run_reproduce(const Args& args);
int run_model(const Args& args);
int run_fk(const Args& args);
int run_ik(const Args& args);
int run_compensate(const Args& args);
int run_calibrate(const Args& args);
int run_observability(const Args& args);
int run_solver_suite(const Args& args);
int run_verify(const Args& args);
int run_export(const Args& args);
int run_validate(const Args& args);
int run_design(const Args& args);
int run_compare(const Args& args);
int run_check(const Args& args);
int run_detect(const Args& args);
int run_project(const Args& args);

}  // namespace kincal::cli
