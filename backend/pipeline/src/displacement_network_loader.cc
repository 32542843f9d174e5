#include "hdvio/pipeline/displacement_network_loader.h"

#include <filesystem>

namespace hdvio {

std::shared_ptr<const learned::DisplacementModel> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights_out) {
  std::string weights;
  network.read("weights", &weights);
  network.finish();
  if (weights_out) *weights_out = weights;
  const std::filesystem::path w(weights);
  const std::string path = w.is_absolute() || experiment_dir.empty()
                               ? weights
                               : (std::filesystem::path(experiment_dir) / w).string();
  return std::make_shared<const learned::DisplacementModel>(learned::DisplacementModel::load(path));
}

}  // namespace hdvio
