#pragma once
// What the trainers (hdvio_train, hdvio_train_displacement) read and do alike: the TCN's shape
// from a `model:` section and the interleaved hold-out of training-flight blocks.
#include <cstddef>
#include <vector>

#include "hdvio/core/config.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::train {

// Reads window, sample_rate_hz, kernel_size, widths and dilations into a (its layers); the
// caller reads its own further keys and calls finish(). InputError if widths and dilations
// differ in length.
void readTcnShape(const ConfigReader& model, learned::TcnArchitecture* a);

// a.validate() as an InputError naming the config file.
void validateTcnShape(const ConfigReader& model, const learned::TcnArchitecture& a);

// Cuts the flight into blocks of block_samples; with every >= 2, block b validates when
// b % every == every / 2 (interleaved, so both sets see every phase of the flight), with
// every == 0 all blocks train.
void splitIntoBlocks(const learned::FlightSamples& flight, std::size_t block_samples,
                     std::size_t every, std::vector<learned::FlightSamples>* train,
                     std::vector<learned::FlightSamples>* validation);

}  // namespace hdvio::train
