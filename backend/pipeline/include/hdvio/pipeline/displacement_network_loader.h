#pragma once
// Reads the `network:` section of the inertial methods (imo/tlio/net_only, gate_io with
// `displacement: network`) into the displacement network(s) that networkDisplacementSource
// (displacement_network_source.h) runs. Strict like every config: unknown keys are errors.
#include <memory>
#include <string>

#include "hdvio/core/config.h"
#include "hdvio/learned/displacement_ensemble.h"

namespace hdvio {

// Loads `network: {weights: <file>}` (one network) or `network: {ensemble: [<file>, ...]}`
// (networks of one recipe from different seeds, learned/displacement_ensemble.h); exactly one of
// the two keys. Paths are relative to the experiment file's folder; *weights (optional) receives
// the file(s) as written, for messages. Throws InputError naming the file for a bad ensemble.
std::shared_ptr<const learned::DisplacementEnsemble> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights = nullptr);

}  // namespace hdvio
