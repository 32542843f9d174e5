#pragma once
// The envelope of a residual-force model's training data (core/model_envelope.h): the range of
// speed, body rate and collective thrust that holds all but the rarest samples, so a spike in a
// training flight (a gyro glitch) does not widen it. hdvio_train writes it into the weight file.
#include <vector>

#include "hdvio/core/model_envelope.h"
#include "hdvio/learned/flight_samples.h"

namespace hdvio::learned {

// The fraction of training samples each bound holds (speed and rate from above, thrust from
// both sides).
constexpr double kEnvelopeQuantile = 0.99;

// Speed |v_W|, rate |gyro| (bias removed where the flight knows it) and thrust |thrust| of every
// sample of the flights; throws std::invalid_argument when they hold no sample.
ModelEnvelope trainingEnvelope(const std::vector<FlightSamples>& flights);

}  // namespace hdvio::learned
