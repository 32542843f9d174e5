#pragma once
// The benchmark's results: every run evaluated with the hdvio_evaluation library (the numbers
// hdvio_eval prints for the same folders), collected into one table like the papers' (rows =
// sequences, columns = methods, ATE_T / ATE_R), plus force RMSE and runtime; written as
// table.md, results.csv, results.json and per-sequence evaluation folders.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hdvio/bench/matrix.h"

namespace hdvio::bench {

struct RunMetrics {
  RunJob job;
  std::string status = "missing";  // ok | failed | missing (never run) | no_groundtruth | n/a
                                   // (a peer on a sequence without images)
  std::string error;               // failed: the log's last error line
  double ate_t_m = NAN;            // ATE translation rmse after the matrix's alignment
  double ate_r_deg = NAN;          // ATE rotation rmse
  double rpe_t_m = NAN;            // evo RPE (10 m) translation rmse
  double velocity_rmse = NAN;      // m/s
  double force_total_rmse = NAN;   // vs f_ext + f_drag (all non-thrust force), m/s^2
  double force_external_rmse = NAN;  // vs f_ext, m/s^2
  std::size_t poses = 0, matched = 0;
  std::vector<std::pair<std::string, double>> stages;  // timing_stages.csv: stage, total s
  double runtime_s = NAN;          // sum of the stages' wall time
  double duration_s = NAN;         // time span of the estimate
  double realtime_factor = NAN;    // duration / runtime (> 1: faster than real time)
  double process_wall_s = NAN;     // whole hdvio_run process, when hdvio_bench ran it
  // Peers: the per-image time the peer printed (a line with "<what> ms/image: mean <x> median
  // <y>", optionally "images <n>"); runtime_s is then mean x images. Experiments on images:
  // frontend + backend per image from timing_images.csv (decoding excluded, as for the peer).
  double ms_per_image_mean = NAN, ms_per_image_median = NAN, ms_per_image_p90 = NAN;
  std::string peer_timing;         // <what>: the word before "ms/image" (what the time counts)
};

// timing_stages.csv's stages and their total seconds, in file order; "stage/part" rows (a
// breakdown of a stage, e.g. frontend/alignment) are left out, so the totals add up to the run.
std::vector<std::pair<std::string, double>> readStages(const std::string& path);

// The peer's timing line in its log (the last line containing "ms/image"); false if none.
bool readPeerTiming(const std::string& log_path, RunMetrics* m, std::size_t* images);

// Evaluates every job's result against its sequence's ground truth; also writes
// <out>/evaluation/<sequence>/ (hdvio_eval's report of all completed runs on that sequence).
std::vector<RunMetrics> collectResults(const Matrix& matrix, const std::vector<RunJob>& jobs,
                                       const std::string& out_dir);

// table.md (returned too, for printing), results.csv, results.json in out_dir.
std::string writeBenchReport(const Matrix& matrix, const std::vector<RunMetrics>& runs,
                             const std::string& out_dir);

// The file where hdvio_bench records the wall time of a run it started.
std::string wallTimeFile(const RunJob& job);

}  // namespace hdvio::bench
