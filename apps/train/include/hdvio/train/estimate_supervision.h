#pragma once
// Supervision without motion capture: the states an hdvio_run result folder holds for a flight
// (stamped_traj_estimate.txt, stamped_velocity_estimate.csv and, when present,
// stamped_bias_estimate.csv) stand in for the flight's ground truth, so hdvio_train learns the
// residual force from positions and velocities a visual-inertial estimate gives (the HDVIO
// paper's loss needs nothing more). The estimate's own error enters the targets; docs/learned.md
// says what to fly so that it stays small.
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::train {

// The folder's states, one per estimated image. InputError naming the file and line for a
// missing or malformed file, a velocity or bias file whose stamps differ from the poses'.
std::vector<GroundTruthState> readEstimatedStates(const std::string& result_dir);

// Replaces seq's ground truth with the estimate of result_dir. InputError naming the trajectory
// file when the estimate does not cover the flight: its first state later than
// kMaxEstimateStartDelay after the first IMU sample (a start takes 0.5-3 s), its last earlier
// than kMaxEstimateEndGap before the last, or a gap of more than kMaxEstimateGap between states.
void superviseWithEstimate(const std::string& result_dir, Sequence* seq);

constexpr double kMaxEstimateStartDelay = 5.0;  // s
constexpr double kMaxEstimateEndGap = 1.0;      // s
constexpr double kMaxEstimateGap = 0.5;         // s

}  // namespace hdvio::train
