#include "kincal/cli/cli_util.hpp"

#include <boost/make_shared.hpp>
#include <iostream>

#include "kincal/cli/common_options.hpp"
#include "kincal/cli/console.hpp"
#include "kincal/cli/plugin_option.hpp"
#include "kincal/cli/project_record.hpp"
#include "kincal/framework/base/nearest_name.hpp"
#include "kincal/framework/least_squares/solver_registry.hpp"
#include "kincal/framework/workflows/calibrate.hpp"

namespace kincal::cli {

namespace {

// "%name%" somewhere in `text`: a placeholder of boost's messages.
bool has_placeholder(const std::string& text) {
  for (auto open = text.find('%'); open != std::string::npos; open = text.find('%', open + 1)) {
    const auto close = text.find('%', open + 1);
    if (close == std::string::npos) return false;
    const std::string name = text.substr(open + 1, close - open - 1);
    if (!name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos)
      return true;
  }
  return false;
}

}  // namespace

std::string option_error_message(const po::error& e, const Args& args,
                                 const po::options_description& options) {
  for (const auto& arg : args) {
    if (!has_placeholder(arg)) continue;
    std::string option;
    if (const auto* named = dynamic_cast<const po::error_with_option_name*>(&e))
      option = named->get_option_name();
    return "bad command line" + (option.empty() ? std::string() : " at option '" + option + "'") +
           ": argument '" + arg +
           "' holds a %name% sequence, which the option parser cannot quote in its message; "
           "check the options (kincal <command> --help)";
  }
  std::string message = e.what();
  if (const auto* unknown = dynamic_cast<const po::unknown_option*>(&e)) {
    std::string given = unknown->get_option_name();
    given.erase(0, given.find_first_not_of('-'));
    std::vector<std::string> known;
    for (const auto& option : options.options())
      if (!option->long_name().empty()) known.push_back(option->long_name());
    const std::string near = nearest_name(given, known);
    if (!near.empty()) message += "; did you mean --" + near + "?";
  }
  return message;
}

namespace {

constexpr const char* kAliasPrefix = "deprecated: the old name of --";

// Moves each alias's value to its current name (so that commands read one name) and says so.
void resolve_deprecated_aliases(const std::string& command, const po::options_description& options,
                                po::variables_map& vm) {
  auto& values = static_cast<std::map<std::string, po::variable_value>&>(vm);
  for (const auto& option : options.options()) {
    const std::string current = deprecated_alias_target(option->description());
    const std::string old = option->long_name();
    if (current.empty() || !vm.count(old)) continue;
    if (vm.count(current) && !vm[current].defaulted())
      throw CliError("give --" + current + " or --" + old + " (its deprecated old name), not both");
    values[current] = values.at(old);
    values.erase(old);
    deprecation_notes().push_back("kincal " + command + ": note: --" + old +
                                  " is deprecated: use --" + current + " (the same option)");
  }
}

}  // namespace

void add_deprecated_alias(po::options_description& options, const std::string& old_name,
                          const std::string& current_name, const po::value_semantic* semantic) {
  options.add(boost::make_shared<po::option_description>(old_name.c_str(), semantic,
                                                         (kAliasPrefix + current_name).c_str()));
}

std::vector<std::string>& deprecation_notes() {
  static std::vector<std::string> notes;
  return notes;
}

std::string deprecated_alias_target(const std::string& description) {
  const std::string prefix = kAliasPrefix;
  if (description.compare(0, prefix.size(), prefix) != 0) return "";
  return description.substr(prefix.size());
}

bool parse_command_line(const std::string& command, const Args& args,
                        po::options_description& options, po::variables_map& vm) {
  add_plugin_option(options);
  options.add_options()("help,h", "show this help")("version", "show kincal's version and exit");
  try {
    // An empty positional description makes boost reject stray words ("too many
    // positional options") instead of ignoring them.
    const po::positional_options_description no_positional;
    const po::parsed_options parsed =
        po::command_line_parser(args).options(options).positional(no_positional).run();
    po::store(parsed, vm);
    po::notify(vm);
    // The options in the order given, for those whose order matters (--free and --fix).
    std::vector<std::pair<std::string, std::string>> order;
    for (const auto& option : parsed.options)
      for (const auto& value : option.value) order.emplace_back(option.string_key, value);
    vm.insert({kOptionOrder, po::variable_value(boost::any(order), false)});
  } catch (const po::error& e) {
    throw CliError(option_error_message(e, args, options));
  }
  // Only now, with every token assigned to its option, are the plug-ins known: a value of
  // another option never names one (cli/plugin_option.hpp).
  load_plugins(vm);
  resolve_deprecated_aliases(command, options, vm);
  if (parse_only()) throw OptionsChecked{};
  if (vm.count("help")) {
    out() << "usage: kincal " << command << " [options]\n" << options;
    return false;
  }
  if (vm.count("version")) {
    out() << version_text();
    return false;
  }
  return true;
}

void validate(boost::any& out, const std::vector<std::string>& values, Seed*, int) {
  po::validators::check_first_occurrence(out);
  const std::string& text = po::validators::get_single_string(values);
  const bool digits_only =
      !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  try {
    if (!digits_only) throw std::invalid_argument(text);
    out = Seed{std::stoull(text)};
  } catch (const std::exception&) {
    throw po::error("--seed '" + text + "': expected a whole number from 0 to 2^64 - 1");
  }
}

std::string option_flag(const std::string& name) {
  return name.rfind("--", 0) == 0 ? name : "--" + name;
}

std::map<std::string, std::string> parse_key_values(const std::vector<std::string>& entries,
                                                    const std::string& option_name) {
  std::map<std::string, std::string> out;
  for (const auto& entry : entries) {
    const auto eq = entry.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CliError(option_flag(option_name) + " '" + entry + "': expected key=value");
    const std::string key = entry.substr(0, eq);
    if (out.count(key))
      throw CliError(option_flag(option_name) + " '" + key + "' is given twice ('" + out[key] +
                     "' and '" + entry.substr(eq + 1) + "')");
    out[key] = entry.substr(eq + 1);
  }
  return out;
}

void check_max_iterations(int value) {
  // 0 would "solve" nothing and report the start as the result (issue 35: calibrate wrote the
  // nominal model as a calibration and exited 0).
  if (value < 1)
    throw CliError("--max-iterations must be at least 1 (got " + std::to_string(value) + ")");
}

std::string default_solver_name() { return SolverRegistry::global().contains("lm") ? "lm" : "gn"; }

void add_solver_options(po::options_description& options) {
  options.add_options()("solver", po::value<std::string>()->default_value(default_solver_name()),
                        "solver backend (kincal list solvers)")(
      "solver-option", po::value<std::vector<std::string>>()->composing(),
      "backend-specific setting key=value (repeatable; see docs/solvers.md)")(
      "max-iterations", po::value<int>()->default_value(200), "iteration limit of the solver")(
      "verbose,v", po::value<int>()->default_value(0)->implicit_value(1),
      "print one line per solver iteration on stderr; --verbose=2 adds lm's trial steps, "
      "Ceres' log and Ipopt's own output");
}

void add_formulation_option(po::options_description& options) {
  options.add_options()("formulation", po::value<std::string>(),
                        "nested (forward kinematics inside every residual) or implicit (the "
                        "poses as unknowns, closed chains only; a failed implicit solve is "
                        "followed by the nested one; docs/theory.md); default: nested");
}

Formulation formulation_choice(const po::variables_map& vm, const MeasurementModel& model) {
  if (!vm.count("formulation")) return default_formulation(model);
  try {
    return parse_formulation(vm["formulation"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw CliError(std::string("--formulation: ") + e.what());
  }
}

namespace {
std::function<bool()>& solver_stop_check() {
  static std::function<bool()> check;
  return check;
}
}  // namespace

void set_solver_stop_check(std::function<bool()> check) { solver_stop_check() = std::move(check); }

void add_loss_option(po::options_description& options) {
  options.add_options()(
      "loss", po::value<std::string>(),
      "robust loss huber:DELTA or cauchy:DELTA (mm) against outliers (lm and ceres)");
}

void reject_loss_as_solver_option(const po::variables_map& vm) {
  if (vm.count("solver-option"))
    for (const auto& entry : vm["solver-option"].as<std::vector<std::string>>())
      if (entry.rfind("loss=", 0) == 0)
        throw CliError("--solver-option '" + entry + "': give the robust loss as --loss " +
                       entry.substr(5) +
                       " (calibrate reports the loss and uses it for the standard deviations)");
}

void apply_loss_option(const po::variables_map& vm, SolverChoice& choice) {
  if (!vm.count("loss")) return;
  try {
    add_robust_loss(vm["loss"].as<std::string>(), *choice.solver, choice.name, choice.options,
                    "--loss", "use --solver lm");
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what());
  }
}

SolverChoice make_solver_choice(const po::variables_map& vm) {
  SolverChoice choice;
  choice.name = vm["solver"].as<std::string>();
  try {
    choice.solver = SolverRegistry::global().create(choice.name);
    if (vm.count("solver-option"))
      choice.options.backend = choice.solver->parse_settings(
          parse_key_values(vm["solver-option"].as<std::vector<std::string>>(), "solver-option"));
    choice.options.max_iterations = vm["max-iterations"].as<int>();
    check_max_iterations(choice.options.max_iterations);
    choice.options.verbosity = vm["verbose"].as<int>();
    if (choice.options.verbosity < 0 || choice.options.verbosity > 2)
      throw CliError("--verbose must be 0, 1 or 2");
    if (const std::function<bool()> stop = solver_stop_check())
      choice.options.callback = [stop](const IterationRecord&, const VectorXd&) {
        return stop() ? CallbackAction::kStop : CallbackAction::kContinue;
      };
    choice.solver->check_options(choice.options);
  } catch (const InvalidSolverOptions& e) {
    throw CliError(e.what());
  }
  return choice;
}

}  // namespace kincal::cli
