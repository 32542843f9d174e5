#pragma once
// Reads the `network:` section of the inertial methods (imo/tlio/net_only, gate_io with
// `displacement: network`) into the displacement network that networkDisplacementSource
// (displacement_network_source.h) runs. Strict like every config: unknown keys are errors.
#include <memory>
#include <string>

#include "hdvio/core/config.h"
#include "hdvio/learned/displacement_model.h"

namespace hdvio {

// Loads `network: {weights: <file>}`, the path relative to the experiment file's folder;
// *weights (optional) receives the path as written.
std::shared_ptr<const learned::DisplacementModel> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights = nullptr);

}  // namespace hdvio
