#include "hdvio/train/training_config.h"

#include <stdexcept>
#include <string>

#include "hdvio/core/error.h"

namespace hdvio::train {

void readTcnShape(const ConfigReader& m, learned::TcnArchitecture* a) {
  m.readInRange("window", &a->window, 1, 10000, true);
  m.readInRange("sample_rate_hz", &a->sample_rate_hz, 1.0, 10000.0, true);
  m.readInRange("kernel_size", &a->kernel_size, 1, 16);
  std::vector<int> widths, dilations;
  m.read("widths", &widths);
  m.read("dilations", &dilations);
  if (widths.size() != dilations.size())
    throw InputError(m.file(), 0, "model.widths and model.dilations must have the same length");
  a->layers.clear();
  for (std::size_t l = 0; l < widths.size(); ++l) a->layers.push_back({widths[l], dilations[l]});
}

void validateTcnShape(const ConfigReader& m, const learned::TcnArchitecture& a) {
  try {
    a.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(m.file(), 0, std::string("model: ") + e.what());
  }
}

void splitIntoBlocks(const learned::FlightSamples& flight, std::size_t block_samples,
                     std::size_t every, std::vector<learned::FlightSamples>* train,
                     std::vector<learned::FlightSamples>* validation) {
  for (std::size_t b = 0; b * block_samples < flight.size(); ++b) {
    const bool validate = every >= 2 && b % every == every / 2;
    (validate ? validation : train)->push_back(flight.slice(b * block_samples, (b + 1) * block_samples));
  }
}

}  // namespace hdvio::train
