#pragma once
// What the trainers (hdvio_train, hdvio_train_displacement) read and do alike: the TCN's shape
// from a `model:` section, the optimizer and stopping keys of a `training:` section, and the
// interleaved hold-out of training-flight blocks.
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

// The `training:` keys both trainers' options have, with the same names and ranges: stride,
// batch size, Adam learning rate, epochs, patience, seed, threads and the time budget. The
// caller reads its own further keys and calls finish().
template <typename TrainingOptions>
void readOptimizationKeys(const ConfigReader& t, TrainingOptions* o) {
  t.readInRange("stride_samples", &o->stride_samples, 1, 100000);
  t.readInRange("batch_size", &o->batch_size, 1, 100000);
  t.readInRange("learning_rate", &o->learning_rate, 1e-8, 1.0);
  t.readInRange("max_epochs", &o->max_epochs, 0, 100000);
  t.readInRange("patience", &o->patience, 1, 100000);
  t.readInRange("seed", &o->seed, 0, 1 << 30);
  t.readInRange("threads", &o->threads, 1, 64);
  t.readInRange("max_minutes", &o->max_minutes, 0.0, 10000.0);
}

// Cuts the flight into blocks of block_samples; with every >= 2, block b validates when
// b % every == every / 2 (interleaved, so both sets see every phase of the flight), with
// every == 0 all blocks train.
void splitIntoBlocks(const learned::FlightSamples& flight, std::size_t block_samples,
                     std::size_t every, std::vector<learned::FlightSamples>* train,
                     std::vector<learned::FlightSamples>* validation);

}  // namespace hdvio::train
