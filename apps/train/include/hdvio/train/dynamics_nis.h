#pragma once
// Is the dynamics factor's weight its real error? On a recorded flight (ground-truth poses and
// velocities, no external force) the [alpha, beta] residual of the point-mass dynamics with a
// drag law (factors/point_mass_dynamics.h) over consecutive intervals, whitened by the factor's
// own covariance (preintegrated thrust and gyro noise + the law's sigma, dragCovariance at the
// recorded velocity): the normalized innovation squared per degree of freedom, 1 when the
// weight is right, of the alpha (position) block, the beta (velocity) block and both together.
#include "hdvio/core/drag_law.h"
#include "hdvio/factors/thrust_preintegration.h"
#include "hdvio/learned/flight_samples.h"

namespace hdvio::train {

struct DynamicsNis {
  double alpha = 0.0, beta = 0.0, joint = 0.0;  // mean NIS / dof
  std::size_t intervals = 0;
};

// Intervals of `samples` steps of the flight's grid from its first sample. InputError if the
// flight has no IMU or is not longer than one interval.
DynamicsNis dynamicsNis(const learned::FlightSamples& flight, const DragLaw& law, std::size_t samples,
                        const ThrustNoiseParams& noise);

}  // namespace hdvio::train
