#pragma once
// Training and evaluation examples of the displacement network, cut from uniformly resampled
// flights (flight_samples.h): window k ends at sample `end`, its inputs are samples
// end - W + 1 .. end (each standing for the interval ending at it), its target the
// ground-truth displacement p[end] - p[end - W] over exactly W / rate seconds.
#include <vector>

#include "hdvio/learned/displacement_model.h"
#include "hdvio/learned/flight_samples.h"

namespace hdvio::learned {

struct DisplacementExample {
  std::size_t flight = 0;  // index into the flight list
  std::size_t end = 0;     // index of the window's last sample
};

// Every `stride`-th window end of every flight, from the first complete window on.
std::vector<DisplacementExample> displacementExamples(const std::vector<FlightSamples>& flights,
                                                      int window, int stride);

// 6 x window: [thrust or specific force; gyro] rotated to the world with the ground-truth
// attitude of each sample (biases as in the flight: ground-truth biases removed when known).
MatrixXf worldWindow(const FlightSamples& flight, std::size_t end, int window,
                     DisplacementInputKind kind);

Vec3 displacementTarget(const FlightSamples& flight, std::size_t end, int window);

// Reference model: integrate R * (thrust or specific force) + g from the ground-truth velocity
// at the window start (thrust ignores drag, so this is the "thrust model" displacement).
Vec3 integratedDisplacement(const FlightSamples& flight, std::size_t end, int window,
                            DisplacementInputKind kind);

}  // namespace hdvio::learned
