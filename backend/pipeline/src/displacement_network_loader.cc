#include "hdvio/pipeline/displacement_network_loader.h"

#include <filesystem>
#include <stdexcept>
#include <vector>

namespace hdvio {

std::shared_ptr<const learned::DisplacementEnsemble> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights_out) {
  std::vector<std::string> files;
  if (network.has("weights") == network.has("ensemble"))
    network.fail("weights", "give exactly one of weights (one network) and ensemble (a list of networks)");
  if (network.has("weights")) {
    files.emplace_back();
    network.read("weights", &files.back());
  } else {
    network.read("ensemble", &files);
    if (files.empty()) network.fail("ensemble", "the list is empty");
  }
  network.finish();
  std::string names;
  std::vector<learned::DisplacementModel> members;
  for (const std::string& f : files) {
    names += (names.empty() ? "" : ", ") + f;
    const std::filesystem::path w(f);
    const std::string path = w.is_absolute() || experiment_dir.empty()
                                 ? f
                                 : (std::filesystem::path(experiment_dir) / w).string();
    members.push_back(learned::DisplacementModel::load(path));
  }
  if (weights_out) *weights_out = names;
  try {
    return std::make_shared<const learned::DisplacementEnsemble>(std::move(members));
  } catch (const std::invalid_argument& e) {
    network.fail("ensemble", e.what());
  }
}

}  // namespace hdvio
