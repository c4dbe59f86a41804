// Example: the kincal program for your own mechanism and sensor. Register them, then hand
// over to the CLI: every command (model, simulate, calibrate, fk, ik, observability, list,
// ...) works with the two-link arm and the inclinometer as with the built-in types.
//
//   kincal-arm model --preset two-link-demo --out arm.json
//   kincal-arm simulate --model arm.json --write-data data.csv
//   kincal-arm calibrate --model arm.json --data data.csv --out calibrated.json

#include <kincal/cli/run.hpp>
#include <kincal/framework/extension/model_registry.hpp>

#include "example_models.hpp"

int main(int argc, char** argv) {
  example::register_example_models(kincal::ModelRegistry::global());
  return kincal::cli::run(argc, argv);
}
