#include "kincal/cli/target_accuracy.hpp"

#include "kincal/cli/commands.hpp"

namespace kincal::cli {

void add_target_option(po::options_description& options) {
  options.add_options()(
      "target", po::value<std::string>(),
      "the pose accuracy you need, a length with its unit and optionally an angle, e.g. 0.1mm "
      "or 0.1mm,0.05deg: the verdicts say whether the pose error meets it");
}

std::optional<TargetAccuracy> target_option(const po::variables_map& vm) {
  if (!vm.count("target")) return std::nullopt;
  return parse_target_accuracy(vm["target"].as<std::string>(), "--target");
}

}  // namespace kincal::cli
