#include "kincal/cli/starts_option.hpp"

namespace kincal::cli {

namespace {

constexpr int kMaxStarts = 10000;

}  // namespace

void add_starts_option(po::options_description& options) {
  options.add_options()(
      "starts", po::value<int>()->default_value(kDefaultStarts),
      "solve from N starting values: the model's, and N - 1 drawn around them from each free "
      "parameter's tolerance (param_error, else prior_std), in parallel and reproducible by "
      "--seed; reports the distinct minima found and continues with the lowest");
}

int starts_option(const po::variables_map& vm) {
  const int starts = vm["starts"].as<int>();
  if (starts < 1 || starts > kMaxStarts)
    throw CliError("--starts " + std::to_string(starts) + ": expected 1 to " +
                   std::to_string(kMaxStarts) + " starting values");
  return starts;
}

}  // namespace kincal::cli
