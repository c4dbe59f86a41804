#pragma once
// --target ACCURACY: the pose accuracy the user needs, e.g. 0.1mm, given
// as a length and optionally an angle (0.1mm,0.001rad or 0.1mm,0.05deg). calibrate, validate
// and design compare their predicted or measured pose error with it
// (framework/analysis/target_accuracy.hpp) and say, in the text, the JSON ("target") and the
// page, whether it is met. The option is defined and parsed here only, so that the three
// commands agree on its spelling and meaning.

#include <optional>

#include "kincal/cli/cli_util.hpp"
#include "kincal/framework/analysis/target_accuracy.hpp"

namespace kincal::cli {

/// Adds --target to a command's options.
void add_target_option(po::options_description& options);

/// --target parsed (parse_target_accuracy); nullopt when not given.
std::optional<TargetAccuracy> target_option(const po::variables_map& vm);

}  // namespace kincal::cli
