#pragma once
// Readers for the trajectory formats users bring to an evaluation. They are deliberately
// independent of the io library: evaluation must read estimator outputs and ground truth even
// where no full sequence exists (a KITTI pose file, an evo test file).
//
// TUM order: "timestamp[s] tx ty tz qx qy qz qw" (8 columns) or the same followed by
//            "vx vy vz" (11 columns, the Blackbird stamped_groundtruth_imu.txt layout).
// KITTI:     12 numbers per line, row-major 3x4 [R|t]; poses correspond by line.
// EuRoC CSV: "#timestamp [ns], p(3), q(w,x,y,z), [v(3), b_w(3), b_a(3)]" (state_groundtruth).
// ASL folder: <dir>/mav0/state_groundtruth_estimate0/data.csv (+ force_groundtruth0/data.csv).
#include <optional>
#include <string>

#include "hdvio/eval/trajectory.h"

namespace hdvio::eval {

enum class TrajectoryFormat { kAuto, kTum, kKitti, kEuroc, kAslFolder };

// "auto", "tum", "kitti", "euroc", "asl"; throws InputError for anything else.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);
std::string formatName(TrajectoryFormat format);

Trajectory readTumTrajectory(const std::string& path);
Trajectory readKittiPoses(const std::string& path);
Trajectory readEurocGroundTruth(const std::string& path);
// Accepts the sequence folder or its mav0 folder.
Trajectory readAslGroundTruth(const std::string& folder);
// The format a path holds, judged from its first data line (or being a folder).
TrajectoryFormat detectTrajectoryFormat(const std::string& path);
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::kAuto);

// "#timestamp [ns],x,y,z": integer stamps are ns, stamps with a decimal point are seconds.
VectorSeries readVectorSeries(const std::string& path);
// "#timestamp [ns],f_ext_x,f_ext_y,f_ext_z,f_drag_x,f_drag_y,f_drag_z".
ForceGroundTruth readForceGroundTruth(const std::string& path);
// The force_groundtruth0 file of an ASL folder, if it has one.
std::optional<std::string> aslForceGroundTruthPath(const std::string& folder);

}  // namespace hdvio::eval
