#pragma once
// A benchmark matrix: experiments x sequences (x seeds), read from a strict YAML file
// (docs/bench.md):
//
//   experiments:                      # one hdvio_run experiment each
//     - {name: vio, config: ../experiments/vio.yaml}
//   sequences:                        # a recorded flight, or a simulator config generated once
//     - {name: clover, dataset: /data/blackbird/clover/val}
//     - {name: tiny, sim: ../sim/ci_tiny.yaml, images: false}
//   peers:                            # optional: external estimators run beside the experiments
//     - {name: openvins, command: ../../../shared/peers/openvins/run.sh}
//   seeds: [1, 2, 3]                  # optional: written as run.seed into copies of the experiments
//   image_noise_sigma: 1.0            # optional, with seeds: written as run.image_noise_sigma
//   metrics: {alignment: posyaw, plots: true}
//
// Relative paths are resolved against the matrix file's folder.
#include <optional>
#include <string>
#include <vector>

#include "hdvio/eval/alignment.h"

namespace hdvio::bench {

struct MatrixExperiment {
  std::string name;    // the column; entries that share it run on disjoint sequences
  std::string config;  // absolute path of the experiment YAML
  // Empty: every sequence. Else only these (e.g. hdvio with the residual-force model of the
  // vehicle that flew them).
  std::vector<std::string> sequences;
  bool runsOn(const std::string& sequence) const;
};

// An external estimator (a peer such as OpenVINS), run once per sequence with images as
// `<command> <ASL folder> <out.txt>`; it writes a TUM trajectory, evaluated like the experiments.
struct MatrixPeer {
  std::string name;
  std::string command;  // absolute path; may be missing (its cells then say so)
};

struct MatrixSequence {
  // Where the flight comes from: a recorded folder, or one the bench generates into
  // <out>/sequences/<name> with hdvio_sim or with the independent simulator indsim
  // (../shared/tools/indsim/indsim.py, run by python3).
  enum class Source { kDataset, kHdvioSim, kIndsim };
  std::string name;
  Source source = Source::kDataset;
  std::string dataset;     // kDataset: absolute path of the flight
  std::string sim_config;  // kHdvioSim: hdvio_sim config; kIndsim: indsim flight JSON (absolute)
  bool sim_images = true;  // false: generated without images (hdvio_sim --no_images, indsim --no-images)
  bool simulated() const { return source != Source::kDataset; }
};

struct Matrix {
  std::string file;
  std::vector<MatrixExperiment> experiments;
  std::vector<MatrixSequence> sequences;
  std::vector<MatrixPeer> peers;  // columns after the experiments
  std::vector<int> seeds;  // empty: each experiment's own run.seed
  // > 0 (only with seeds): the seeded copies also get run.image_noise_sigma, so that runs on
  // camera images differ by seed (the visual methods' noise on decoded images), and the peers
  // run once per seed on a copy of the sequence whose images carry that seed's noise.
  double image_noise_sigma = 0.0;
  eval::AlignmentType alignment = eval::AlignmentType::kPosYaw;
  bool plots = true;
};

// Throws InputError (file:line: problem) for unknown keys, missing files, bad or repeated
// names (experiments and peers share one namespace: the table's columns), an empty matrix, or a
// sequence with neither or both of `dataset` and `sim`. A missing peer command is not an error.
Matrix loadMatrix(const std::string& path);

// One run of the matrix: an hdvio_run process, or a peer's command.
struct RunJob {
  std::string sequence;
  std::string experiment;   // the column: an experiment's or a peer's name
  std::optional<int> seed;
  std::string label;        // "<sequence>/<experiment>[/seed<k>]", what --only matches
  std::string dataset;      // the sequence hdvio_run reads
  std::string config;       // the experiment YAML hdvio_run reads (a seeded copy with seeds)
  std::string original_config;  // the matrix's experiment YAML (what a seeded copy copies)
  std::string dir;          // <out>/runs/<sequence>/<experiment>[/seed<k>]
  std::string result_dir;   // <dir>/result: hdvio_run --out; a peer's estimate is moved into it
  std::string log;          // <dir>/log.txt: the process's stdout and stderr
  std::string peer_command;    // peers: the command (empty for hdvio_run runs)
  std::string not_applicable;  // peers: why the peer cannot run on this sequence (no images)
  // Seeded peers (image_noise_sigma > 0): the sequence whose noisy copy `dataset` is
  // (<out>/sequences/<name>.noise_seed<k>, written by hdvio_image_noise before the runs).
  std::string noisy_copy_of;
  bool peer() const { return !peer_command.empty(); }
};

// Where a sequence is read from: its dataset, or <out>/sequences/<name> for simulated ones.
std::string sequencePath(const MatrixSequence& seq, const std::string& out_dir);
// kIndsim: the simulator beside the flight's folder (<indsim>/flights/<flight>.json ->
// <indsim>/indsim.py).
std::string indsimScript(const MatrixSequence& seq);

// Every (sequence, experiment[, seed]) and (sequence, peer) whose label contains `only` (all when
// empty), sequences in matrix order. Paths only; nothing is written.
std::vector<RunJob> expandJobs(const Matrix& matrix, const std::string& out_dir,
                               const std::string& only);

// With seeds: writes job.config, a copy of the experiment with run.seed set and relative file
// paths made absolute (so learned weights etc. still resolve from the copy's folder).
void prepareJobConfig(const Matrix& matrix, const RunJob& job);

// The run finished: hdvio_run moves its result into place only after writing everything; a
// peer's estimate is moved there after its command exited 0 (finishPeerRun).
bool runCompleted(const RunJob& job);

// Where a peer writes its estimate while it runs (<dir>/estimate.partial.txt).
std::string peerPartialEstimate(const RunJob& job);
// The estimate a completed peer run leaves: <result_dir>/stamped_traj_estimate.txt.
std::string peerEstimate(const RunJob& job);
// After the peer's command exited 0: moves its estimate into result/. False (and a line
// "error: ..." appended to its log) when it wrote none.
bool finishPeerRun(const RunJob& job);

}  // namespace hdvio::bench
