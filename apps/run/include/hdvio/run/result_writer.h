#pragma once
// Writes an estimator's results in the formats of FORMATS.md: the TUM-order trajectory plus
// CSVs of velocity, biases and forces (IMU frame: external, learned residual, their sum) with the
// same timestamps, per-frame timing, per-stage timing and the effective configuration. Everything goes to a temporary folder that is
// renamed into place at the end, so a failed run never leaves partial results.
#include <string>
#include <vector>

#include "hdvio/backend/imo/imo_runner.h"
#include "hdvio/core/nav_state.h"

namespace hdvio::run {

struct FrameTiming {
  Timestamp t = 0;
  double backend_ms = 0.0;
  int solver_iterations = 0;
  int landmarks = 0;
  int observations = 0;
  bool keyframe = false;
};

// Time spent in one stage of a pipeline (frontend, backend, network, filter, ...): wall clock
// for the visual pipelines, thread CPU time for the inertial ones (docs/running.md).
struct StageTiming {
  std::string stage;
  double total_s = 0.0;
  int calls = 0;
};

struct RunResults {
  std::vector<NavState> states;
  std::vector<FrameTiming> timing;   // per frame (visual methods)
  std::vector<StageTiming> stages;   // per stage, whole run
  std::string effective_config;  // YAML
  bool has_force = false;
  // The model's non-thrust force (IMU frame, m/s^2) at each state, parallel to states: learned
  // residual force plus the drag law at the state's velocity, if configured; empty when the
  // method has neither (then the total non-thrust force is f_ext alone).
  std::vector<Vec3> residual_force_B;
  // Displacement updates of the inertial filters (innovations.csv); empty for other methods.
  std::vector<imo::UpdateInnovation> innovations;
};

// Throws InputError unless out_dir is absent, empty, or an earlier hdvio result (which will be
// replaced): never deletes a folder it did not write.
void checkOutputFolder(const std::string& out_dir);
void writeResults(const RunResults& results, const std::string& out_dir);

}  // namespace hdvio::run
