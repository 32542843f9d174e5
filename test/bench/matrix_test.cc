// The benchmark matrix: strict parsing with file:line errors, the run list, seeded copies.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "hdvio/bench/matrix.h"
#include "hdvio/core/error.h"

namespace hdvio::bench {
namespace {
namespace fs = std::filesystem;

class BenchMatrix : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hdvio_bench_matrix_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "exp");
    std::ofstream(dir_ / "exp" / "weights.txt") << "w\n";
    std::ofstream(dir_ / "exp" / "a.yaml") << "method: vio\nresidual_force: {weights: weights.txt}\n";
    std::ofstream(dir_ / "exp" / "b.yaml") << "method: vimo\n";
    std::ofstream(dir_ / "sim.yaml") << "name: x\n";
    fs::create_directories(dir_ / "data");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& text) {
    const fs::path p = dir_ / "matrix.yaml";
    std::ofstream(p) << text;
    return p.string();
  }
  // The InputError's message, or "" if loading succeeds.
  std::string loadError(const std::string& text) {
    try {
      loadMatrix(write(text));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

const char* kGood =
    "experiments:\n"
    "  - {name: a, config: exp/a.yaml}\n"
    "  - {name: b, config: exp/b.yaml}\n"
    "sequences:\n"
    "  - {name: real, dataset: data}\n"
    "  - {name: simulated, sim: sim.yaml, images: false}\n";

TEST_F(BenchMatrix, ReadsExperimentsSequencesAndDefaults) {
  const Matrix m = loadMatrix(write(kGood));
  ASSERT_EQ(m.experiments.size(), 2u);
  ASSERT_EQ(m.sequences.size(), 2u);
  EXPECT_EQ(m.experiments[1].config, (dir_ / "exp" / "b.yaml").string());
  EXPECT_EQ(m.sequences[0].dataset, (dir_ / "data").string());
  EXPECT_FALSE(m.sequences[0].simulated());
  EXPECT_TRUE(m.sequences[1].simulated());
  EXPECT_FALSE(m.sequences[1].sim_images);
  EXPECT_TRUE(m.seeds.empty());
  EXPECT_EQ(m.alignment, eval::AlignmentType::kPosYaw);
  EXPECT_TRUE(m.plots);
}

// A flight of the independent simulator: its JSON, the script beside its folder, with or
// without images; the bench writes it where it writes hdvio_sim's.
TEST_F(BenchMatrix, IndsimFlightsAreGeneratedSequences) {
  fs::create_directories(dir_ / "indsim" / "flights");
  std::ofstream(dir_ / "indsim" / "indsim.py") << "# simulator\n";
  std::ofstream(dir_ / "indsim" / "flights" / "f.json") << "{}\n";
  const Matrix m = loadMatrix(write(std::string(kGood) +
                                    "  - {name: other, indsim: indsim/flights/f.json}\n"
                                    "  - {name: slow, indsim: indsim/flights/f.json, images: false}\n"));
  ASSERT_EQ(m.sequences.size(), 4u);
  EXPECT_EQ(m.sequences[1].source, MatrixSequence::Source::kHdvioSim);
  const MatrixSequence& q = m.sequences[2];
  EXPECT_EQ(q.source, MatrixSequence::Source::kIndsim);
  EXPECT_TRUE(q.simulated());
  EXPECT_TRUE(q.sim_images);
  EXPECT_FALSE(m.sequences[3].sim_images);
  EXPECT_EQ(q.sim_config, (dir_ / "indsim" / "flights" / "f.json").string());
  EXPECT_EQ(indsimScript(q), (dir_ / "indsim" / "indsim.py").string());
  EXPECT_EQ(sequencePath(q, (dir_ / "out").string()), (dir_ / "out" / "sequences" / "other").string());
}

TEST_F(BenchMatrix, RejectsBadInputWithFileAndLine) {
  const std::string file = (dir_ / "matrix.yaml").string();
  struct Case {
    std::string yaml;
    std::string expected;  // part of the message
  };
  const std::vector<Case> cases = {
      {std::string(kGood) + "metricz: {}\n", "metricz': unknown key"},
      {std::string(kGood) + "metrics: {alignment: best}\n", "not one of"},
      {std::string(kGood) + "seeds: [1, 1]\n", "distinct"},
      {std::string(kGood) + "image_noise_sigma: 1.0\n", "image_noise_sigma': needs 'seeds'"},
      {std::string(kGood) + "seeds: [1]\nimage_noise_sigma: -1\n", "image_noise_sigma"},
      {"experiments:\n  - {name: a, config: exp/missing.yaml}\nsequences:\n  - {name: r, dataset: data}\n",
       ":2: key 'experiments[0].config': no such file"},
      {"experiments:\n  - {name: a, config: exp/a.yaml, extra: 1}\nsequences:\n  - {name: r, dataset: data}\n",
       "experiments[0].extra': unknown key"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\nsequences:\n  - {name: r, dataset: data, sim: sim.yaml}\n",
       "exactly one of 'dataset', 'sim' and 'indsim'"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\nsequences:\n  - {name: r}\n",
       "exactly one of 'dataset', 'sim' and 'indsim'"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\nsequences:\n  - {name: r, sim: sim.yaml, indsim: indsim/flights/f.json}\n",
       "exactly one of 'dataset', 'sim' and 'indsim'"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\nsequences:\n  - {name: r, indsim: sim.yaml}\n",
       ":4: key 'sequences[0].indsim (its simulator)': no such file"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\nsequences:\n  - {name: r, dataset: data, images: false}\n",
       "images': unknown key"},
      {"experiments:\n  - {name: a, config: exp/a.yaml}\n  - {name: a, config: exp/b.yaml}\n"
       "sequences:\n  - {name: r, dataset: data}\n",
       ":3: experiment name 'a' appears twice"},
      {"experiments:\n  - {name: a/b, config: exp/a.yaml}\nsequences:\n  - {name: r, dataset: data}\n",
       "use letters, digits"},
      {"experiments: []\nsequences:\n  - {name: r, dataset: data}\n", "list is empty"},
      {"sequences:\n  - {name: r, dataset: data}\n", "'experiments': required key is missing"},
  };
  for (const Case& c : cases) {
    const std::string e = loadError(c.yaml);
    EXPECT_EQ(e.rfind(file, 0), 0u) << "no file name in: " << e << "\n for:\n" << c.yaml;
    EXPECT_NE(e.find(c.expected), std::string::npos) << e << "\n for:\n" << c.yaml;
  }
}

// One column, a config per group of sequences (hdvio with each vehicle's model): each run
// reads its own group's config, also in its seeded copy.
TEST_F(BenchMatrix, ExperimentsListingSequencesShareAColumn) {
  const std::string two = "experiments:\n"
                          "  - {name: a, config: exp/a.yaml, sequences: [real]}\n"
                          "  - {name: a, config: exp/b.yaml, sequences: [simulated]}\n"
                          "sequences:\n"
                          "  - {name: real, dataset: data}\n"
                          "  - {name: simulated, sim: sim.yaml, images: false}\n";
  const Matrix m = loadMatrix(write(two + "seeds: [4]\n"));
  ASSERT_EQ(m.experiments.size(), 2u);
  const std::vector<RunJob> jobs = expandJobs(m, (dir_ / "out").string(), "");
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].label, "real/a/seed4");
  EXPECT_EQ(jobs[0].original_config, (dir_ / "exp" / "a.yaml").string());
  EXPECT_EQ(jobs[1].label, "simulated/a/seed4");
  EXPECT_EQ(jobs[1].original_config, (dir_ / "exp" / "b.yaml").string());
  prepareJobConfig(m, jobs[1]);
  EXPECT_EQ(YAML::LoadFile(jobs[1].config)["method"].as<std::string>(), "vimo");  // b.yaml's

  const std::string file = (dir_ / "matrix.yaml").string();
  for (const auto& [yaml, expected] : std::vector<std::pair<std::string, std::string>>{
           {"experiments:\n  - {name: a, config: exp/a.yaml, sequences: [real]}\n"
            "  - {name: a, config: exp/b.yaml, sequences: [real]}\n"
            "sequences:\n  - {name: real, dataset: data}\n",
            ":3: experiment 'a' runs twice on sequence 'real'"},
           {"experiments:\n  - {name: a, config: exp/a.yaml, sequences: [real]}\n"
            "  - {name: a, config: exp/b.yaml}\n"
            "sequences:\n  - {name: real, dataset: data}\n",
            ":3: experiment name 'a' appears twice"},
           {"experiments:\n  - {name: a, config: exp/a.yaml, sequences: [reel]}\n"
            "sequences:\n  - {name: real, dataset: data}\n",
            ":2: key 'experiments[0].sequences': no sequence 'reel'"}}) {
    const std::string e = loadError(yaml);
    EXPECT_EQ(e.rfind(file, 0), 0u) << e;
    EXPECT_NE(e.find(expected), std::string::npos) << e;
  }
}

TEST_F(BenchMatrix, ExpandsRunsInMatrixOrderAndFiltersThem) {
  Matrix m = loadMatrix(write(std::string(kGood) + "seeds: [3, 5]\n"));
  const std::string out = (dir_ / "out").string();
  const std::vector<RunJob> all = expandJobs(m, out, "");
  ASSERT_EQ(all.size(), 8u);
  EXPECT_EQ(all[0].label, "real/a/seed3");
  EXPECT_EQ(all[1].label, "real/a/seed5");
  EXPECT_EQ(all[2].label, "real/b/seed3");
  EXPECT_EQ(all[7].label, "simulated/b/seed5");
  EXPECT_EQ(all[7].dataset, (dir_ / "out" / "sequences" / "simulated").string());
  EXPECT_EQ(all[7].result_dir, (dir_ / "out" / "runs" / "simulated" / "b" / "seed5" / "result").string());
  EXPECT_EQ(all[0].dataset, (dir_ / "data").string());
  const std::vector<RunJob> only = expandJobs(m, out, "simulated/a");
  ASSERT_EQ(only.size(), 2u);
  EXPECT_EQ(only[0].label, "simulated/a/seed3");
  EXPECT_TRUE(expandJobs(m, out, "nothing").empty());
  m.seeds.clear();
  const std::vector<RunJob> unseeded = expandJobs(m, out, "");
  ASSERT_EQ(unseeded.size(), 4u);
  EXPECT_EQ(unseeded[3].label, "simulated/b");
  EXPECT_EQ(unseeded[3].config, (dir_ / "exp" / "b.yaml").string());  // the original
}

TEST_F(BenchMatrix, PeersAreColumnsAfterTheExperimentsAndNotApplicableWithoutImages) {
  fs::create_directories(dir_ / "asl" / "mav0" / "cam0" / "data");
  const Matrix m = loadMatrix(write(
      "experiments:\n  - {name: a, config: exp/a.yaml}\n"
      "peers:\n  - {name: ov, command: peers/run.sh}\n  - {name: abs, command: /no/such/run.sh}\n"
      "sequences:\n  - {name: real, dataset: data}\n  - {name: asl, dataset: asl}\n"
      "  - {name: rendered, sim: sim.yaml}\n  - {name: tracks, sim: sim.yaml, images: false}\n"
      "seeds: [1, 2]\n"));
  ASSERT_EQ(m.peers.size(), 2u);
  EXPECT_EQ(m.peers[0].command, (dir_ / "peers" / "run.sh").string());  // missing: not an error
  EXPECT_EQ(m.peers[1].command, "/no/such/run.sh");
  const std::vector<RunJob> all = expandJobs(m, (dir_ / "out").string(), "");
  ASSERT_EQ(all.size(), 16u);  // per sequence: a x 2 seeds, then ov and abs (not seeded)
  EXPECT_EQ(all[2].label, "real/ov");
  EXPECT_FALSE(all[0].peer());
  EXPECT_TRUE(all[2].peer());
  EXPECT_FALSE(all[2].seed.has_value());
  EXPECT_EQ(all[2].peer_command, m.peers[0].command);
  EXPECT_EQ(all[2].result_dir, (dir_ / "out" / "runs" / "real" / "ov" / "result").string());
  EXPECT_NE(all[2].not_applicable.find("no mav0/cam0/data"), std::string::npos);  // not ASL
  EXPECT_EQ(all[6].label, "asl/ov");
  EXPECT_EQ(all[6].not_applicable, "");
  EXPECT_EQ(all[10].label, "rendered/ov");
  EXPECT_EQ(all[10].not_applicable, "");
  EXPECT_EQ(all[10].dataset, (dir_ / "out" / "sequences" / "rendered").string());
  EXPECT_EQ(all[15].label, "tracks/abs");
  EXPECT_NE(all[15].not_applicable.find("images: false"), std::string::npos);
  const std::vector<RunJob> only = expandJobs(m, (dir_ / "out").string(), "/ov");
  ASSERT_EQ(only.size(), 4u);
  EXPECT_EQ(only[3].label, "tracks/ov");
  EXPECT_FALSE(runCompleted(only[1]));
  fs::create_directories(only[1].result_dir);
  std::ofstream(peerEstimate(only[1])) << "0 0 0 0 0 0 0 1\n";
  EXPECT_TRUE(runCompleted(only[1]));  // a peer's run is its estimate in result/
}

TEST_F(BenchMatrix, RejectsBadPeersWithFileAndLine) {
  const std::string file = (dir_ / "matrix.yaml").string();
  const std::string head = "experiments:\n  - {name: a, config: exp/a.yaml}\n";
  const std::string seqs = "sequences:\n  - {name: r, dataset: data}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + "peers:\n  - {name: a, command: run.sh}\n" + seqs, ":4: peer name 'a' appears twice"},
      {head + "peers:\n  - {name: p, command: run.sh, args: x}\n" + seqs, "peers[0].args': unknown key"},
      {head + "peers:\n  - {name: p}\n" + seqs, "command': required key is missing"},
      {head + "peers:\n  - {name: p, command: ''}\n" + seqs, ":4: key 'peers[0].command': empty"},
      {head + "peers:\n  - {name: 'p q', command: run.sh}\n" + seqs, "use letters, digits"},
  };
  for (const auto& c : cases) {
    const std::string e = loadError(c.first);
    EXPECT_EQ(e.rfind(file, 0), 0u) << "no file name in: " << e << "\n for:\n" << c.first;
    EXPECT_NE(e.find(c.second), std::string::npos) << e << "\n for:\n" << c.first;
  }
}

TEST_F(BenchMatrix, SeededCopyKeepsTheExperimentAndItsRelativeFiles) {
  const Matrix m = loadMatrix(write(std::string(kGood) + "seeds: [42]\n"));
  const RunJob job = expandJobs(m, (dir_ / "out").string(), "real/a")[0];
  prepareJobConfig(m, job);
  const YAML::Node copy = YAML::LoadFile(job.config);
  EXPECT_EQ(copy["method"].as<std::string>(), "vio");
  EXPECT_EQ(copy["run"]["seed"].as<int>(), 42);
  EXPECT_EQ(copy["residual_force"]["weights"].as<std::string>(), (dir_ / "exp" / "weights.txt").string());
  EXPECT_FALSE(copy["run"]["image_noise_sigma"]);
  EXPECT_FALSE(runCompleted(job));

  // With image noise, every seeded copy carries it beside its seed.
  const Matrix noisy = loadMatrix(write(std::string(kGood) + "seeds: [7]\nimage_noise_sigma: 1.5\n"));
  const RunJob noisy_job = expandJobs(noisy, (dir_ / "out2").string(), "real/a")[0];
  prepareJobConfig(noisy, noisy_job);
  const YAML::Node noisy_copy = YAML::LoadFile(noisy_job.config);
  EXPECT_EQ(noisy_copy["run"]["seed"].as<int>(), 7);
  EXPECT_DOUBLE_EQ(noisy_copy["run"]["image_noise_sigma"].as<double>(), 1.5);
}

}  // namespace
}  // namespace hdvio::bench
