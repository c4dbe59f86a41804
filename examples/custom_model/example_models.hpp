#pragma once
// Registers the example's mechanism and sensor types and a preset that uses them. Call it
// once, before anything reads model files or lists models.

#include <kincal/framework/extension/model_registry.hpp>

namespace example {

void register_example_models(kincal::ModelRegistry& registry);

}  // namespace example
