#pragma once
// How wrong a residual-force model is on a flight with a measured force, and how fast that
// error moves: what the dynamics factor must be told about the model (its honest uncertainty).
//
// The error of a hybrid model (thrust + drag law + network) has three parts with different
// homes in the smoother: white noise (the accelerometer's own, and sample-to-sample model
// noise) that the preintegration covariances carry; a slowly moving part (thrust lag and scale
// the network misses, unmodelled aerodynamics) that only the external force's random walk can
// follow; and the rest. modelErrorWalk measures the second from held-out flights, so the
// estimator's force walk is at least what the model needs (AdaptiveForceWalk raises it further
// where a flight shows more, e.g. wind).
#include <vector>

#include "hdvio/core/drag_law.h"
#include "hdvio/core/lie.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

// measured - (thrust + law at the recorded velocity + network), body frame, m/s^2, for the
// samples from the first full network window on (all samples without a network). Throws
// std::invalid_argument if the flight has no measured force.
std::vector<Vec3> forceModelError(const FlightSamples& flight, const Tcn* network, const DragLaw& law);

// The random-walk density (m/s^2/sqrt(s), isotropic: the mean over the three axes of q) of the
// slow part of error series (contiguous stretches sampled at rate_hz). Each series is averaged
// over blocks of block_s; for a Wiener process of density q plus white noise of per-sample
// variance s^2, consecutive block means a, b differ by E(b - a)^2 = q (T_a + T_b) / 3 +
// s^2 (1 / n_a + 1 / n_b) per axis (as AdaptiveForceWalk, backend/). s^2 comes from the
// consecutive-sample differences (E d^2 = 2 s^2 for white noise), so a model whose error is
// white (only the accelerometer's noise) gets ~0. Returns 0 when no series has two blocks.
double modelErrorWalk(const std::vector<std::vector<Vec3>>& series, double rate_hz, double block_s = 0.5);

}  // namespace hdvio::learned
