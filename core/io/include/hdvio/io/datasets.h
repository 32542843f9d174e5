#pragma once
// Readers for the public quadrotor datasets in /work/shared/data, each mapped to the Sequence
// conventions of FORMATS.md (see docs/datasets.md for the per-dataset mapping and checks).
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

// Blackbird in the learned-inertial-odometry HDF5 layout: a folder holding data.hdf5 (+ the
// optional stamped_groundtruth_imu.txt), or the data.hdf5 path itself.
Sequence readBlackbird(const std::string& path, const ReadOptions& options = {});

// DIDO: a folder holding data.hdf5, or the file itself. meas_rpm may have 4 columns or 5 (a
// leading timestamp column, ignored: rows are aligned with 'ts').
Sequence readDido(const std::string& path, const ReadOptions& options = {});

// NeuroBEM segment CSV (header row of named columns, time 't' in seconds).
Sequence readNeuroBem(const std::string& csv_path, const ReadOptions& options = {});

// The NeuroBEM model's own prediction and the residuals stored next to each sample (body frame).
struct NeuroBemForceSample {
  Timestamp t = 0;
  Vec3 force = Vec3::Zero();             // neurobem_f_*   [N]
  Vec3 torque = Vec3::Zero();            // neurobem_tau_* [N m]
  Vec3 residual_force = Vec3::Zero();    // residual_f_*   [N]
  Vec3 residual_torque = Vec3::Zero();   // residual_tau_* [N m]
};
std::vector<NeuroBemForceSample> readNeuroBemForces(const std::string& csv_path);

// Vehicle constants documented with the data (README in /work/shared/data).
constexpr double kBlackbirdMass = 0.915;                // kg
constexpr double kNeuroBemMass = 0.772;                 // kg

}  // namespace hdvio::io
