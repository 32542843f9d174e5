// hdvio_bench with peers (external estimators such as OpenVINS): a fake peer — a shell script
// that writes the ground truth with a known zig-zag as its estimate and prints a time per image
// — becomes a column with the ATE hdvio_eval gives its estimate and that time; a missing or
// failing peer is a note in its cells (not an exit-1 failure), a sequence without images is
// "n/a"; --only, reruns, --force and --emit-jobs work for peer runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/core.hpp>

#include "bench_test_helpers.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/pipeline/visual_sequence_runner.h"

namespace {
namespace fs = std::filesystem;

using namespace hdvio::test;  // bench, runShell, readFile, jsonNumber (bench_test_helpers.h)
using Outcome = CommandOutcome;

// The table row of a sequence.
std::string row(const std::string& table, const std::string& sequence) {
  std::stringstream ss(table);
  std::string line;
  while (std::getline(ss, line))
    if (line.rfind("| " + sequence + " |", 0) == 0) return line;
  return "";
}

const std::string kSource = HDVIO_SOURCE_DIR;

class BenchPeer : public ::testing::Test {
 protected:
  // One ASL folder (ci_tiny without rendering, plus an empty cam0/data: the fake peer reads no
  // image) and a matrix with a fake, a failing and a missing peer.
  static void SetUpTestSuite() {
    dir_ = freshTempDir("hdvio_bench_peer_");
    fs::create_directories(dir_ / "peers");
    const Outcome sim = runShell(std::string(HDVIO_SIM_BINARY) + " --config " + kSource +
                                 "/config/sim/ci_tiny.yaml --no_images --out " + seq().string());
    ASSERT_EQ(sim.exit_code, 0) << sim.output;
    fs::create_directories(seq() / "mav0" / "cam0" / "data");
    // ASL ground truth (t [ns], p, q_wxyz, ...) -> TUM (t [s], p, q_xyzw), x += +-5 cm alternately.
    std::ofstream(dir_ / "peers" / "fake.sh")
        << "#!/bin/sh\nset -e\n"
           "awk -F, '!/^#/ {printf \"%.9f %.9f %s %s %s %s %s %s\\n\", $1 / 1e9, "
           "$2 + (NR % 2 ? 0.05 : -0.05), $3, $4, $6, $7, $8, $5}' "
           "\"$1/mav0/state_groundtruth_estimate0/data.csv\" > \"$2\"\n"
           "echo \"images 50  fake_update ms/image: mean 2.50  median 2.00  (threads=1)\"\n";
    std::ofstream(dir_ / "peers" / "broken.sh")
        << "#!/bin/sh\necho 'error: the fake peer broke' >&2\nexit 3\n";
    fs::permissions(dir_ / "peers" / "fake.sh", fs::perms::owner_all);
    fs::permissions(dir_ / "peers" / "broken.sh", fs::perms::owner_all);
    std::ofstream(matrix())
        << "experiments:\n  - {name: vio, config: " << kSource << "/config/experiments/vio.yaml}\n"
        << "peers:\n  - {name: peer_fake, command: peers/fake.sh}\n"  // relative to the matrix
        << "  - {name: peer_broken, command: " << (dir_ / "peers" / "broken.sh").string() << "}\n"
        << "  - {name: peer_absent, command: /no/such/peer/run.sh}\n"
        << "sequences:\n  - {name: asl, dataset: " << seq().string() << "}\n"
        << "  - {name: tracks, sim: " << kSource << "/config/sim/ci_tiny.yaml, images: false}\n"
        << "metrics: {plots: false}\n";
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path seq() { return dir_ / "asl_seq"; }
  static fs::path matrix() { return dir_ / "matrix.yaml"; }
  // hdvio_eval's ATE translation rmse of an estimate file against the ASL folder.
  static double evalAte(const fs::path& estimate, const std::string& tag) {
    const fs::path out = dir_ / ("eval_" + tag);
    const Outcome e = runShell(std::string(HDVIO_EVAL_BINARY) + " --gt " + seq().string() +
                               " --est p=" + estimate.string() + " --out " + out.string());
    EXPECT_EQ(e.exit_code, 0) << e.output;
    const std::string metrics = readFile(out / "metrics.json");
    return jsonNumber(metrics, "rmse", metrics.find("ate_translation_m"));
  }
  static fs::path dir_;
};
fs::path BenchPeer::dir_;

TEST_F(BenchPeer, PeerColumnsBesideTheExperiments) {
  const fs::path out = dir_ / "out";
  // Peers only (--only): no hdvio_run, and `tracks` is not generated (its peer cells are n/a).
  const Outcome o = bench("--matrix " + matrix().string() + " --out " + out.string() + " --only peer_");
  ASSERT_EQ(o.exit_code, 0) << o.output;  // failing / missing peers are notes, not failures
  EXPECT_NE(o.output.find("3 runs to do, 0 already complete"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("note: 2 peer runs have no numbers"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(out / "sequences" / "tracks"));
  const std::string table = readFile(out / "table.md");
  EXPECT_NE(table.find("| sequence | peer_fake | peer_broken | peer_absent |"), std::string::npos) << table;
  EXPECT_NE(row(table, "asl").find("| 0.050 / 0.00 |"), std::string::npos) << table;
  EXPECT_NE(row(table, "asl").find("failed: error: the fake peer broke"), std::string::npos) << table;
  EXPECT_NE(row(table, "asl").find("failed: error: peer command not found: /no/such/peer/run.sh"),
            std::string::npos) << table;
  EXPECT_EQ(row(table, "tracks"), "| tracks | n/a | n/a | n/a |");  // first grid: ATE
  EXPECT_NE(table.find("`fake_update` 2.50 ms/image mean, 2.00 median"), std::string::npos) << table;
  EXPECT_NE(table.find("; 2.50 ms/image |"), std::string::npos) << table;  // runtime column
  EXPECT_NE(table.find("tracks: n/a: the sequence is generated without images"), std::string::npos) << table;
  EXPECT_EQ(table.find("Runs without numbers"), std::string::npos) << table;  // peers: notes

  // The peer's numbers are hdvio_eval's for its estimate (same ground truth, alignment,
  // association): the zig-zag's 5 cm.
  const fs::path estimate = out / "runs" / "asl" / "peer_fake" / "result" / "stamped_traj_estimate.txt";
  ASSERT_TRUE(fs::exists(estimate));
  EXPECT_FALSE(fs::exists(out / "runs" / "asl" / "peer_fake" / "estimate.partial.txt"));
  const double ate = evalAte(estimate, "fake");
  EXPECT_NEAR(ate, 0.05, 2e-3);
  const std::string results = readFile(out / "results.json");
  const std::size_t run = results.find("\"experiment\": \"peer_fake\"");
  ASSERT_NE(run, std::string::npos) << results;
  EXPECT_NE(results.find("\"status\": \"ok\"", run), std::string::npos);
  EXPECT_NEAR(jsonNumber(results, "ate_t_m", run), ate, 1e-12 * ate);
  EXPECT_DOUBLE_EQ(jsonNumber(results, "ms_per_image_mean", run), 2.5);
  EXPECT_DOUBLE_EQ(jsonNumber(results, "ms_per_image_median", run), 2.0);
  EXPECT_NEAR(jsonNumber(results, "runtime_s", run), 50 * 2.5e-3, 1e-12);  // images x mean
  EXPECT_GT(jsonNumber(results, "realtime_factor", run), 0.0);
  EXPECT_TRUE(fs::exists(out / "evaluation" / "asl" / "metrics.json"));

  // A rerun skips the completed peer run (the failing ones run again); --force reruns it.
  const Outcome again = bench("--matrix " + matrix().string() + " --out " + out.string() + " --only peer_");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("2 runs to do, 1 already complete"), std::string::npos) << again.output;
  const Outcome forced = bench("--matrix " + matrix().string() + " --out " + out.string() +
                               " --only asl/peer_fake --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_NE(forced.output.find("1 runs to do, 0 already complete"), std::string::npos) << forced.output;
  EXPECT_NE(row(readFile(out / "table.md"), "asl").find("| 0.050 / 0.00 |"), std::string::npos);
}

// A peer writing a stamp twice (as estimators do, e.g. evo's ORB-SLAM example) is evaluated as
// hdvio_eval does, and the run says so.
TEST_F(BenchPeer, RepeatedPeerStampsAreAWarning) {
  std::ofstream(dir_ / "peers" / "repeat.sh")
      << "#!/bin/sh\nset -e\n\"$(dirname \"$0\")/fake.sh\" \"$1\" \"$2\"\n"
         "awk 'NR == 3 {print} {print}' \"$2\" > \"$2.tmp\" && mv \"$2.tmp\" \"$2\"\n";
  fs::permissions(dir_ / "peers" / "repeat.sh", fs::perms::owner_all);
  const fs::path m = dir_ / "repeat_matrix.yaml";
  std::ofstream(m) << "experiments:\n  - {name: vio, config: " << kSource << "/config/experiments/vio.yaml}\npeers:\n  - {name: peer_repeat, command: peers/repeat.sh}\n"
                   << "sequences:\n  - {name: asl, dataset: " << seq().string() << "}\nmetrics: {plots: false}\n";
  const fs::path out = dir_ / "repeat_out";
  const Outcome o = bench("--matrix " + m.string() + " --out " + out.string() + " --only peer_");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("hdvio_bench: asl/peer_repeat: warning: "), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("1 pose repeats the previous timestamp"), std::string::npos) << o.output;
  EXPECT_NE(row(readFile(out / "table.md"), "asl").find("| 0.0"), std::string::npos) << readFile(out / "table.md");
}

TEST_F(BenchPeer, EmittedPeerLinesRunAndAggregate) {
  const fs::path out = dir_ / "emit";
  const Outcome o = bench("--matrix " + matrix().string() + " --out " + out.string() +
                          " --only peer_fake --emit-jobs -");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  std::vector<std::string> runs;
  std::stringstream ss(o.output);
  for (std::string l; std::getline(ss, l);)
    if (l.find("peers/fake.sh ") != std::string::npos) runs.push_back(l);
  ASSERT_EQ(runs.size(), 1u) << o.output;  // asl only: the n/a run is not emitted
  EXPECT_NE(runs[0].find(seq().string() + " " + (out / "runs/asl/peer_fake/estimate.partial.txt").string()),
            std::string::npos) << runs[0];
  const Outcome ran = runShell(runs[0]);
  ASSERT_EQ(ran.exit_code, 0) << ran.output;
  const Outcome agg = bench("--matrix " + matrix().string() + " --out " + out.string() +
                            " --only peer_fake --aggregate-only");
  EXPECT_EQ(agg.exit_code, 0) << agg.output;
  EXPECT_NE(row(readFile(out / "table.md"), "asl").find("| asl | 0.050 / 0.00 |"), std::string::npos)
      << readFile(out / "table.md");
}

// Over noise seeds (seeds + image_noise_sigma) a peer runs once per seed, on a copy of the
// sequence whose images carry that seed's noise: the pixels hdvio_run's seeded run decodes.
TEST(BenchNoisyPeer, PeersRunPerSeedOnImagesWithThatSeedsNoise) {
  const fs::path dir = freshTempDir("hdvio_bench_noisy_peer_");
  const fs::path seq = dir / "img";
  const Outcome sim = runShell(std::string(HDVIO_SIM_BINARY) + " --config " + kSource +
                               "/config/sim/ci_images.yaml --out " + seq.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  // The fake peer: the ground truth as its estimate, and which folder it read.
  std::ofstream(dir / "peer.sh")
      << "#!/bin/sh\nset -e\necho \"$1\" > \"$2.dataset\"\n"
         "awk -F, '!/^#/ {printf \"%.9f %.9f %s %s %s %s %s %s\\n\", $1 / 1e9, $2, $3, $4, $6, $7, "
         "$8, $5}' \"$1/mav0/state_groundtruth_estimate0/data.csv\" > \"$2\"\n";
  fs::permissions(dir / "peer.sh", fs::perms::owner_all);
  std::ofstream(dir / "matrix.yaml")
      << "experiments:\n  - {name: vio, config: " << kSource << "/config/experiments/vio.yaml}\n"
      << "peers:\n  - {name: peer_fake, command: peer.sh}\n"
      << "sequences:\n  - {name: img, dataset: " << seq.string() << "}\n"
      << "seeds: [1, 2]\nimage_noise_sigma: 2.0\nmetrics: {plots: false}\n";
  const fs::path out = dir / "out";
  const Outcome o = bench("--matrix " + (dir / "matrix.yaml").string() + " --out " +
                          out.string() + " --only peer_fake --jobs 2");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("2 runs to do, 0 already complete"), std::string::npos) << o.output;
  const hdvio::Sequence original = hdvio::io::readAsl(seq.string());
  const cv::Mat first = hdvio::io::loadImage(original.images.front(), &*original.camera);
  for (int k : {1, 2}) {
    const fs::path copy = out / "sequences" / ("img.noise_seed" + std::to_string(k));
    const fs::path run = out / "runs" / "img" / "peer_fake" / ("seed" + std::to_string(k));
    EXPECT_EQ(readFile(run / "estimate.partial.txt.dataset"), copy.string() + "\n");
    EXPECT_TRUE(fs::exists(run / "result" / "stamped_traj_estimate.txt"));
    const hdvio::Sequence noisy = hdvio::io::readAsl(copy.string());
    ASSERT_EQ(noisy.images.size(), original.images.size());
    const cv::Mat got = hdvio::io::loadImage(noisy.images.front(), &*noisy.camera);
    const cv::Mat want = hdvio::withImageNoise(first, 2.0, k, original.images.front().t);
    EXPECT_EQ(cv::norm(got, want, cv::NORM_INF), 0.0) << "seed " << k;
    EXPECT_GT(cv::norm(got, first, cv::NORM_L1), 0.5 * first.total()) << "seed " << k;
  }
  const std::string csv = readFile(out / "results.csv");
  EXPECT_NE(csv.find("img,peer_fake,1,ok"), std::string::npos) << csv;
  EXPECT_NE(csv.find("img,peer_fake,2,ok"), std::string::npos) << csv;
  EXPECT_NE(readFile(out / "table.md").find("  - img, seed 2: "), std::string::npos);
  // Emitted jobs write the copies before the runs (phase 1b); existing copies are not rewritten.
  const Outcome e = bench("--matrix " + (dir / "matrix.yaml").string() + " --out " +
                          (dir / "emit").string() + " --only peer_fake --emit-jobs -");
  ASSERT_EQ(e.exit_code, 0) << e.output;
  const std::size_t copies = e.output.find("# phase 1b");
  ASSERT_NE(copies, std::string::npos) << e.output;
  EXPECT_NE(e.output.find("hdvio_image_noise --dataset " + seq.string() + " --sigma 2 --seed 2",
                          copies), std::string::npos) << e.output;
  EXPECT_LT(copies, e.output.find("# phase 2"));
  fs::remove_all(dir);
}

// The real matrix: flights of both simulators, three noise seeds, OpenVINS a column of every
// sequence (on each seed's noisy copy) through the shared peer script, and hdvio with the
// residual-force model of the simulator that rendered the flight.
TEST_F(BenchPeer, SimImagesMatrixRunsOpenVinsBesideTheFrontendExperiments) {
  for (const std::string sequence : {"race_v15_wind", "ind_circle_wind"}) {
    SCOPED_TRACE(sequence);
    const fs::path out = dir_ / "sim_images";
    const Outcome o = bench("--matrix " + kSource + "/config/bench/sim_images.yaml --out " +
                            out.string() + " --emit-jobs - --only " + sequence);
    ASSERT_EQ(o.exit_code, 0) << o.output;
    const bool indsim = sequence[0] == 'i';
    int renders = 0, openvins = 0, hdvio_runs = 0;
    std::stringstream ss(o.output);
    for (std::string l; std::getline(ss, l);) {
      if (l.find(indsim ? "/shared/tools/indsim/indsim.py" : "hdvio_sim ") != std::string::npos) {
        ++renders;
        EXPECT_EQ(l.find("no_images"), std::string::npos) << l;
        EXPECT_EQ(l.find("no-images"), std::string::npos) << l;
      }
      if (l.find("/peers/openvins/run.sh " + (out / "sequences" / sequence).string() + ".noise_seed") !=
          std::string::npos)
        ++openvins;
      if (l.find("hdvio_run --config " + (out / "runs" / sequence).string()) != std::string::npos)
        ++hdvio_runs;
    }
    EXPECT_EQ(renders, 1) << o.output;
    EXPECT_EQ(openvins, 3) << o.output;
    // vio, vimo, hdvio, hdvio with the slow-flight model x ground-truth / own start x 3 seeds
    EXPECT_EQ(hdvio_runs, 24) << o.output;
    const std::string copy = readFile(out / "runs" / sequence / "hdvio_gt" / "seed2" / "experiment.yaml");
    EXPECT_NE(copy.find(indsim ? "indsim_drag.tcn" : "sim_drag.tcn"), std::string::npos) << copy;
    const std::string slow = readFile(out / "runs" / sequence / "hdvio_slow_gt" / "seed2" / "experiment.yaml");
    EXPECT_NE(slow.find(indsim ? "indsim_slow.tcn" : "/sim_slow.tcn"), std::string::npos) << slow;
  }
}

}  // namespace
