#pragma once
// Writes an estimator's results in the formats of FORMATS.md: the TUM-order trajectory plus
// CSVs of velocity, biases and forces (IMU frame: external, learned residual, their sum) with the
// same timestamps, per-frame and per-image timing, per-stage timing and the effective configuration. Everything goes to a temporary folder that is
// renamed into place at the end, so a failed run never leaves partial results.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hdvio/backend/imo/imo_stepper.h"
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

// One camera image of a visual pipeline (timing_images.csv): where its time went, wall clock.
struct ImageTiming {
  Timestamp t = 0;
  double load_ms = 0.0;      // what the estimator's thread waited for the decoded image
  double frontend_ms = 0.0;
  double backend_ms = 0.0;   // backend step plus its feedback into the frontend's map
  int tracked_features = 0;
  bool frontend_keyframe = false;
  bool used_by_backend = false;
};

// Time spent in one stage of a pipeline (frontend, backend, network, filter, ...): wall clock
// for the visual pipelines, thread CPU time for the inertial ones (docs/running.md).
struct StageTiming {
  StageTiming(std::string name, double total, int n, std::vector<double> per_call_ms = {})
      : stage(std::move(name)), total_s(total), calls(n), call_ms(std::move(per_call_ms)) {}
  std::string stage;
  double total_s = 0.0;
  int calls = 0;
  std::vector<double> call_ms;  // per call, when known: p50 / p90 / max in timing_stages.csv
};

struct RunResults {
  std::vector<NavState> states;
  std::vector<FrameTiming> timing;   // per frame (visual methods)
  std::vector<StageTiming> stages;   // per stage, whole run
  std::vector<ImageTiming> images;   // per camera image (visual methods on images)
  std::string effective_config;  // YAML
  bool has_force = false;
  // The model's non-thrust force (IMU frame, m/s^2) at each state, parallel to states: learned
  // residual force plus the drag law at the state's velocity, if configured; empty when the
  // method has neither (then the total non-thrust force is f_ext alone).
  std::vector<Vec3> residual_force_B;
  // Displacement updates of the inertial filters (innovations.csv); empty for other methods.
  std::vector<imo::UpdateInnovation> innovations;
  // The input's time span when the config limited the run to part of the sequence
  // (run.start_offset_s, run.duration_s); empty for a run on all of it. The evaluation takes
  // its rpg sub-trajectory lengths from the ground truth of this span.
  std::optional<std::pair<Timestamp, Timestamp>> input_span;
};

// Summary of per-call times; quantiles by nearest rank (a time that was measured). All NaN if empty.
struct TimeQuantiles {
  double mean = 0.0, p50 = 0.0, p90 = 0.0, max = 0.0;
};
TimeQuantiles timeQuantiles(std::vector<double> ms);

// Frontend + backend per image from a timing_images.csv written by writeResults; empty if the
// file is absent (methods without images).
std::vector<double> readImageProcessingMs(const std::string& path);

// Throws InputError unless out_dir is absent, empty, or an earlier hdvio result (which will be
// replaced): never deletes a folder it did not write.
void checkOutputFolder(const std::string& out_dir);
void writeResults(const RunResults& results, const std::string& out_dir);

}  // namespace hdvio::run
