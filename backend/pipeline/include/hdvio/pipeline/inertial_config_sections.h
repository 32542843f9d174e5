#pragma once
// What the inertial methods' experiment files (hdvio_run: imo, tlio, model_ekf, net_only,
// gate_io) hold besides the filter, model, gate and network sections: the span to run on
// (`run:`), the thrust from rotor speeds (`thrust:`, not gate_io) and gate_io's `displacement`
// choice, read into what inertial_sequence_runner.h and inertial_estimator.h take. docs/imo.md,
// docs/gate_io.md. Strict like every config: unknown keys are errors.
#include <string>

#include "hdvio/core/config.h"
#include "hdvio/pipeline/inertial_estimator.h"

namespace hdvio {

// `run:`, the IMU span of imuSpanWithGroundTruth (inertial_sequence_runner.h).
struct InertialRunSpan {
  double start_offset_s = 0.0;  // after the first IMU sample inside the ground truth
  double duration_s = 0.0;      // <= 0: to the end
};

// Reads `run:` into *span (defaults = what it holds) and calls r.finish().
void readInertialRunSection(const ConfigReader& r, InertialRunSpan* span);

// `thrust:`, for sequences with rotor speeds but no thrust samples: the collective thrust
// coefficient_over_mass * |speeds|^2 * axis (body frame); 0 = no thrust from rotor speeds.
struct RotorThrust {
  double coefficient_over_mass = 0.0;
  Vec3 axis = Vec3::UnitZ();
};

// Reads `thrust:` into *thrust (defaults = what it holds) and calls t.finish(). InputError
// (naming config_path) for an axis that is not a unit vector.
void readThrustSection(const ConfigReader& t, const std::string& config_path, RotorThrust* thrust);

// gate_io's top-level `displacement: none | network` (default none): no displacement source,
// or the network's displacements as filter updates.
DisplacementUse readGateIoDisplacement(const ConfigReader& cfg);

}  // namespace hdvio
