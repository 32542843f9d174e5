#pragma once
// The drag law (core/drag_law.h) on resampled flights, as the learned-model tools use it: fitted
// by least squares on the mass-normalized force beyond the thrust (accelerometer minus its known
// bias, minus thrust) against the ground-truth body velocity and the collective thrust, and
// evaluated at the recorded velocity (which makes it use part of the state, as NeuroBEM does).
#include <string>
#include <vector>

#include "hdvio/core/drag_law.h"
#include "hdvio/learned/flight_samples.h"

namespace hdvio::train {

// The law and its sigma (withFittedSigma; with no sigma term the per-axis residual RMS) on these
// flights, body rates from their gyro. InputError if a flight has no IMU or there are fewer
// than 100 samples in all.
DragLaw fitDragLawOn(const std::vector<learned::FlightSamples>& flights, const DragTerms& terms,
                     const DragSigmaTerms& sigma_terms = {});

// The law's sigma per sample at the recorded body velocity, gyro and thrust.
std::vector<Vec3> lawSigma(const learned::FlightSamples& flight, const DragLaw& law);

// thrust + law at the recorded body velocity, per sample (mass-normalized, body frame).
std::vector<Vec3> thrustPlusLaw(const learned::FlightSamples& flight, const DragLaw& law);

// Term names (a non-empty subset of linear, rotor, quadratic, lift) as DragTerms; else an
// InputError naming file and `what` (the key or flag).
DragTerms parseDragTerms(const std::vector<std::string>& names, const std::string& file, const std::string& what);

// Sigma term names (any of constant, speed, rate, thrust; constant is always in) as
// DragSigmaTerms; else an InputError naming file and `what`.
DragSigmaTerms parseDragSigmaTerms(const std::vector<std::string>& names, const std::string& file,
                                   const std::string& what);

}  // namespace hdvio::train
