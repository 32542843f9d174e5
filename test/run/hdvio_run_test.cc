// hdvio_run end to end on a tiny simulated flight: results and their formats, and one clear
// error with exit code 2 for bad experiments and for sequences that lack what a method needs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "../common/run_command.h"
#include "../learned/deterministic_tcn.h"
#include "hdvio/core/config.h"
#include "hdvio/core/drag_law.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/io/asl.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;
// The force walk's floor of the weight-file tests (backend section lines).
const std::string kFloor = "  force_random_walk: 0.02\n";

using Outcome = test::CommandOutcome;

// Rows of a "#timestamp [ns],x,y,z" CSV: stamp and vector.
std::vector<std::pair<long long, Vec3>> readForceCsv(const fs::path& path) {
  std::vector<std::pair<long long, Vec3>> rows;
  std::ifstream f(path);
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    long long t = 0;
    char comma = 0;
    Vec3 v;
    ss >> t >> comma >> v.x() >> comma >> v.y() >> comma >> v.z();
    if (ss) rows.push_back({t, v});
  }
  return rows;
}
// force_groundtruth0/data.csv rows: stamp, external force and drag (body frame).
struct ForceTruth {
  long long t;
  Vec3 external, drag;
};
std::vector<ForceTruth> readForceTruth(const fs::path& path) {
  std::vector<ForceTruth> rows;
  std::ifstream f(path);
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    ForceTruth r{};
    if (ss >> r.t >> r.external.x() >> r.external.y() >> r.external.z() >> r.drag.x() >> r.drag.y() >> r.drag.z())
      rows.push_back(r);
  }
  return rows;
}

Outcome run(const std::string& args) {
  return test::runCommand(std::string(HDVIO_RUN_BINARY) + " " + args);
}

class HdvioRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // CTest runs each test in its own process, possibly in parallel: one folder per process.
    dir_ = fs::temp_directory_path() / ("hdvio_run_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    auto config = sim::loadSimConfig(
        ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_tiny.yaml"));
    config.camera.rate_hz = 20.0;
    const auto result = sim::Simulator(config).simulate();
    io::writeAsl(result.sequence, (dir_ / "seq").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string writeConfig(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // hdvio from the ground-truth start with the weight file and the backend section's lines: one
  // of its CSV outputs (out folder o_<name>).
  static std::vector<std::pair<long long, Vec3>> hdvioOutput(const std::string& name, const std::string& weights,
                                                             const std::string& backend,
                                                             const std::string& csv = "stamped_force_estimate.csv") {
    const std::string config = writeConfig(
        name + ".yaml", "method: hdvio\nbackend:\n" + backend + "residual_force: {type: tcn, weights: " + weights +
                            "}\nrun: {init_from_groundtruth: true}\n");
    const Outcome o = run("--config " + config + " --dataset " + (dir_ / "seq").string() + " --out " +
                          (dir_ / ("o_" + name)).string() + " --evaluate=false");
    EXPECT_EQ(o.exit_code, 0) << o.output;
    return readForceCsv(dir_ / ("o_" + name) / csv);
  }
  static fs::path dir_;
};
fs::path HdvioRun::dir_;

TEST_F(HdvioRun, WritesResultsInTheDocumentedFormats) {
  const std::string cfg = writeConfig("vimo.yaml", "method: vimo\nrun: {init_from_groundtruth: true}\n");
  const fs::path out = dir_ / "out_vimo";
  const Outcome o = run("--config " + cfg + " --dataset " + (dir_ / "seq").string() + " --out " + out.string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  for (const char* f : {"stamped_traj_estimate.txt", "stamped_velocity_estimate.csv",
                        "stamped_bias_estimate.csv", "stamped_force_estimate.csv", "timing.csv",
                        "config.yaml"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream traj(out / "stamped_traj_estimate.txt");
  std::string header, line;
  std::getline(traj, header);
  EXPECT_EQ(header, "# timestamp[s] tx ty tz qx qy qz qw");
  int rows = 0;
  while (std::getline(traj, line)) {
    std::istringstream ss(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(ss >> x) << line;
    EXPECT_NEAR(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7], 1.0, 1e-6);
    ++rows;
  }
  EXPECT_GT(rows, 40);
  std::ifstream cfg_out(out / "config.yaml");
  std::stringstream eff;
  eff << cfg_out.rdbuf();
  EXPECT_NE(eff.str().find("num_keyframes: 10"), std::string::npos) << "defaults are written";
}

// The force outputs: f_ext, the provider's residual force and their sum, row by row; for vimo
// (no residual model) the total equals f_ext and no residual file is written.
TEST_F(HdvioRun, WritesExternalResidualAndTotalForces) {
  const std::string weights = (dir_ / "residual.tcn").string();
  learned::saveTcnWeights(learned::testing::deterministicTcn(), weights, "hdvio_run test");
  const std::string cfg = writeConfig(
      "hdvio_tcn.yaml", "method: hdvio\nresidual_force: {type: tcn, weights: " + weights +
                            "}\nrun: {init_from_groundtruth: true}\n");
  const fs::path out = dir_ / "out_hdvio_tcn";
  Outcome o = run("--config " + cfg + " --dataset " + (dir_ / "seq").string() + " --out " +
                  out.string() + " --evaluate=false");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const auto ext = readForceCsv(out / "stamped_force_estimate.csv");
  const auto res = readForceCsv(out / "stamped_residual_force_estimate.csv");
  const auto total = readForceCsv(out / "stamped_total_force_estimate.csv");
  ASSERT_GT(ext.size(), 40u);
  ASSERT_EQ(res.size(), ext.size());
  ASSERT_EQ(total.size(), ext.size());
  double residual_norm = 0.0;
  for (std::size_t k = 0; k < ext.size(); ++k) {
    ASSERT_EQ(res[k].first, ext[k].first);
    ASSERT_EQ(total[k].first, ext[k].first);
    EXPECT_LT((total[k].second - ext[k].second - res[k].second).norm(), 1e-8) << k;  // 9 decimals
    residual_norm = std::max(residual_norm, res[k].second.norm());
  }
  EXPECT_GT(residual_norm, 1e-3) << "the network's force is written, not zeros";

  const std::string vimo = writeConfig("vimo_forces.yaml", "method: vimo\nrun: {init_from_groundtruth: true}\n");
  const fs::path out_vimo = dir_ / "out_vimo_forces";
  o = run("--config " + vimo + " --dataset " + (dir_ / "seq").string() + " --out " +
          out_vimo.string() + " --evaluate=false");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  EXPECT_FALSE(fs::exists(out_vimo / "stamped_residual_force_estimate.csv"));
  const auto vimo_ext = readForceCsv(out_vimo / "stamped_force_estimate.csv");
  const auto vimo_total = readForceCsv(out_vimo / "stamped_total_force_estimate.csv");
  ASSERT_EQ(vimo_total.size(), vimo_ext.size());
  for (std::size_t k = 0; k < vimo_ext.size(); ++k)
    EXPECT_EQ(vimo_total[k].second, vimo_ext[k].second) << k;
}

// The diagnostic perfect residual model: the residual force written at each state is the
// simulator's true drag there; a sequence without ground-truth forces is a clear error.
TEST_F(HdvioRun, GroundTruthResidualForceIsTheTrueDragAndNeedsIt) {
  const std::string cfg = writeConfig(
      "hdvio_truth.yaml",
      "method: hdvio\nresidual_force: {type: ground_truth}\nrun: {init_from_groundtruth: true}\n");
  const fs::path out = dir_ / "out_hdvio_truth";
  Outcome o = run("--config " + cfg + " --dataset " + (dir_ / "seq").string() + " --out " +
                  out.string() + " --evaluate=false");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  std::vector<std::pair<long long, Vec3>> drag;  // the simulator's drag
  for (const ForceTruth& r : readForceTruth(dir_ / "seq" / "mav0" / "force_groundtruth0" / "data.csv"))
    drag.push_back({r.t, r.drag});
  ASSERT_GT(drag.size(), 100u);
  const auto res = readForceCsv(out / "stamped_residual_force_estimate.csv");
  ASSERT_GT(res.size(), 40u);
  double largest = 0.0;
  for (const auto& [t, f] : res) {
    const auto hi = std::lower_bound(drag.begin(), drag.end(), t,
                                     [](const auto& d, long long v) { return d.first < v; });
    ASSERT_TRUE(hi != drag.end()) << t;
    Vec3 expected = hi->second;
    if (hi->first != t) {
      ASSERT_TRUE(hi != drag.begin()) << t;
      const auto lo = hi - 1;
      const double a = static_cast<double>(t - lo->first) / static_cast<double>(hi->first - lo->first);
      expected = (1.0 - a) * lo->second + a * hi->second;
    }
    EXPECT_LT((f - expected).norm(), 1e-6) << t;  // written with 9 decimals
    largest = std::max(largest, f.norm());
  }
  EXPECT_GT(largest, 0.1) << "the flight has drag";

  const fs::path no_forces = dir_ / "no_forces";
  fs::copy(dir_ / "seq", no_forces, fs::copy_options::recursive);
  fs::remove_all(no_forces / "mav0" / "force_groundtruth0");
  o = run("--config " + cfg + " --dataset " + no_forces.string() + " --out " + (dir_ / "o_nf").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("needs the simulator's force_groundtruth0"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o_nf"));
}

// The drag law at the estimated velocity (backend.drag_linear / drag_quadratic, with the adaptive
// force walk): the model force written at each state is the law at that state's estimated body
// velocity, and it is close to the simulator's true drag.
TEST_F(HdvioRun, DragLawIsEvaluatedAtTheEstimatedVelocity) {
  const std::string cfg = writeConfig(
      "hdvio_drag.yaml",
      "method: hdvio\nbackend:\n  drag_linear: [0.3, 0.3, 0.05]\n  drag_quadratic: [0.01, 0.01, 0.01]\n"
      "  force_random_walk: 0.05\n  force_walk_adaptive: true\nresidual_force: {type: zero}\n"
      "run: {init_from_groundtruth: true}\n");
  const fs::path out = dir_ / "out_hdvio_drag";
  const Outcome o = run("--config " + cfg + " --dataset " + (dir_ / "seq").string() + " --out " +
                        out.string() + " --evaluate=false");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  DragLaw law;
  law.linear = Vec3(0.3, 0.3, 0.05);
  law.quadratic = Vec3::Constant(0.01);
  const auto res = readForceCsv(out / "stamped_residual_force_estimate.csv");
  const auto vel = readForceCsv(out / "stamped_velocity_estimate.csv");
  std::ifstream traj(out / "stamped_traj_estimate.txt");
  std::string line;
  std::vector<Quat> q;
  while (std::getline(traj, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t, x, y, z, qx, qy, qz, qw;
    if (ss >> t >> x >> y >> z >> qx >> qy >> qz >> qw) q.push_back(Quat(qw, qx, qy, qz));
  }
  ASSERT_GT(res.size(), 40u);
  ASSERT_EQ(res.size(), vel.size());
  ASSERT_EQ(res.size(), q.size());
  for (std::size_t k = 0; k < res.size(); ++k) {
    // No rotor term here, so the thrust does not matter.
    const Vec3 expected = law.force(q[k].normalized().conjugate() * vel[k].second, DragLaw::kHoverThrust);
    EXPECT_LT((res[k].second - expected).norm(), 1e-5) << k;  // files hold 9 decimals / digits
  }
  // The total non-thrust force (law + external) against the simulator's (external + drag at
  // the airspeed: the wind is left to the external force), nearest ground-truth sample.
  std::vector<std::pair<long long, Vec3>> truth;
  for (const ForceTruth& r : readForceTruth(dir_ / "seq" / "mav0" / "force_groundtruth0" / "data.csv"))
    truth.push_back({r.t, r.external + r.drag});
  const auto total = readForceCsv(out / "stamped_total_force_estimate.csv");
  ASSERT_EQ(total.size(), res.size());
  double err2 = 0.0, true2 = 0.0, law_only2 = 0.0;
  for (std::size_t k = 0; k < total.size(); ++k) {
    const long long t = total[k].first;
    const auto it = std::lower_bound(truth.begin(), truth.end(), t,
                                     [](const auto& d, long long v) { return d.first < v; });
    ASSERT_TRUE(it != truth.end());
    err2 += (total[k].second - it->second).squaredNorm();
    law_only2 += (res[k].second - it->second).squaredNorm();
    true2 += it->second.squaredNorm();
  }
  std::printf("total force rms error %.3f (law alone %.3f), true rms %.3f m/s^2\n",
              std::sqrt(err2 / total.size()), std::sqrt(law_only2 / total.size()),
              std::sqrt(true2 / total.size()));
  EXPECT_LT(err2, 0.15 * 0.15 * true2);
  EXPECT_LT(err2, 0.5 * law_only2);  // the external force takes up the wind

  const std::string negative =
      writeConfig("neg_drag.yaml", "method: hdvio\nbackend:\n  drag_linear: [0.3, -0.3, 0.05]\n");
  Outcome bad = run("--config " + negative + " --dataset " + (dir_ / "seq").string() + " --out " +
                    (dir_ / "o_neg").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("'backend.drag_linear': values must be non-negative"), std::string::npos)
      << bad.output;
  // The sigma's growth terms are backend keys too (an unknown key would be a different error).
  const std::string negative_sigma = writeConfig(
      "neg_sigma.yaml", "method: hdvio\nbackend:\n  drag_linear: [0.3, 0.3, 0.05]\n  drag_sigma_rate: [0.2, -0.2, 0.5]\n");
  bad = run("--config " + negative_sigma + " --dataset " + (dir_ / "seq").string() + " --out " +
            (dir_ / "o_neg_sigma").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("'backend.drag_sigma_rate': values must be non-negative"), std::string::npos)
      << bad.output;
  const std::string low_max = writeConfig(
      "low_max.yaml",
      "method: hdvio\nbackend:\n  force_random_walk: 0.5\n  force_walk_adaptive: true\n"
      "  force_walk_max: 0.1\n");
  bad = run("--config " + low_max + " --dataset " + (dir_ / "seq").string() + " --out " +
            (dir_ / "o_max").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("force_walk_max': must be >= force_random_walk"), std::string::npos)
      << bad.output;
  const std::string vid = writeConfig("vid_drag.yaml", "method: vid\nbackend:\n  drag_linear: [0.3, 0.3, 0.05]\n");
  bad = run("--config " + vid + " --dataset " + (dir_ / "seq").string() + " --out " +
            (dir_ / "o_vid").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("vid_drag.yaml: key 'backend.drag_linear': vid's force prior"), std::string::npos)
      << bad.output;
  const std::string truth_and_law = writeConfig(
      "truth_drag.yaml", "method: hdvio\nbackend:\n  drag_linear: [0.3, 0.3, 0.05]\n"
                         "residual_force: {type: ground_truth}\n");
  bad = run("--config " + truth_and_law + " --dataset " + (dir_ / "seq").string() + " --out " +
            (dir_ / "o_truth").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("ground_truth is the whole drag"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "o_truth"));
  EXPECT_FALSE(fs::exists(dir_ / "o_neg"));
  EXPECT_FALSE(fs::exists(dir_ / "o_max"));
  EXPECT_FALSE(fs::exists(dir_ / "o_vid"));
}

// A hybrid weight file (version 3) brings its drag law; the backend keys may repeat it, not
// contradict it.
TEST_F(HdvioRun, HybridWeightFileBringsItsDragLaw) {
  const std::string weights = (dir_ / "hybrid.tcn").string();
  learned::TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.05);
  info.drag_law.quadratic = Vec3::Constant(0.01);
  info.drag_law.rotor = Vec3(0.1, 0.05, 0.0);
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, weights, "hdvio_run test");
  const std::string rf = "residual_force: {type: tcn, weights: " + weights + "}\n";
  const std::string same = writeConfig(
      "hybrid_same.yaml", "method: hdvio\nbackend:\n  drag_linear: [0.3, 0.3, 0.05]\n"
                          "  drag_quadratic: [0.01, 0.01, 0.01]\n  drag_rotor: [0.1, 0.05, 0]\n" + rf +
                          "run: {init_from_groundtruth: true}\n");
  const std::string plain =
      writeConfig("hybrid.yaml", "method: hdvio\n" + rf + "run: {init_from_groundtruth: true}\n");
  const Outcome a = run("--config " + same + " --dataset " + (dir_ / "seq").string() + " --out " +
                        (dir_ / "o_same").string() + " --evaluate=false");
  const Outcome b = run("--config " + plain + " --dataset " + (dir_ / "seq").string() + " --out " +
                        (dir_ / "o_plain").string() + " --evaluate=false");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << b.output;
  // Same law either way: the same estimate (to round-off), and the law is in the model force.
  const auto va = readForceCsv(dir_ / "o_same" / "stamped_velocity_estimate.csv");
  const auto vb = readForceCsv(dir_ / "o_plain" / "stamped_velocity_estimate.csv");
  ASSERT_GT(va.size(), 40u);
  ASSERT_EQ(va.size(), vb.size());
  for (std::size_t k = 0; k < va.size(); ++k) EXPECT_LT((va[k].second - vb[k].second).norm(), 1e-6) << k;
  // A different linear term, or the same law without its rotor term, contradicts the file.
  for (const std::string& keys : {std::string("  drag_linear: [0.2, 0.3, 0.05]\n"),
                                  std::string("  drag_linear: [0.3, 0.3, 0.05]\n  drag_quadratic: [0.01, 0.01, 0.01]\n")}) {
    const std::string other = writeConfig("hybrid_other.yaml", "method: hdvio\nbackend:\n" + keys + rf);
    const Outcome c = run("--config " + other + " --dataset " + (dir_ / "seq").string() + " --out " +
                          (dir_ / "o_other").string());
    EXPECT_EQ(c.exit_code, 2);
    EXPECT_NE(c.output.find("hybrid_other.yaml: backend.drag_* keys differ from the drag law"), std::string::npos)
        << c.output;
    EXPECT_FALSE(fs::exists(dir_ / "o_other"));
  }
}

// The weight file's sigma is the law's own residual, which its network explains: the dynamics
// do not take it from the file (it cost 2.5x the ATE on a bench flight), only from backend keys.
TEST_F(HdvioRun, HybridWeightFileSigmaIsTheLawsNotTheModels) {
  learned::TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.05);
  info.drag_law.quadratic = Vec3::Constant(0.01);
  const std::string without = (dir_ / "hybrid_nosigma.tcn").string();
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, without, "hdvio_run test");
  info.drag_law.sigma = Vec3::Constant(0.3);
  info.drag_law.sigma_speed = Vec3::Constant(0.1);
  const std::string with = (dir_ / "hybrid_sigma.tcn").string();
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, with, "hdvio_run test");
  const auto estimate = [&](const std::string& name, const std::string& weights, const std::string& keys) {
    return hdvioOutput(name, weights, "  drag_linear: [0.3, 0.3, 0.05]\n" + keys, "stamped_velocity_estimate.csv");
  };
  const std::string quadratic = "  drag_quadratic: [0.01, 0.01, 0.01]\n";
  const auto plain = estimate("s_plain", without, quadratic);
  const auto from_file = estimate("s_file", with, quadratic);
  const auto asked = estimate("s_asked", with, quadratic + "  drag_sigma: [0.3, 0.3, 0.3]\n"
                                                          "  drag_sigma_speed: [0.1, 0.1, 0.1]\n");
  ASSERT_GT(plain.size(), 40u);
  ASSERT_EQ(plain.size(), from_file.size());
  ASSERT_EQ(plain.size(), asked.size());
  double moved = 0.0;
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_LT((from_file[k].second - plain[k].second).norm(), 1e-9) << k;
    moved = std::max(moved, (asked[k].second - plain[k].second).norm());
  }
  EXPECT_GT(moved, 1e-4);  // asked for, the sigma weights the dynamics
}

// A weight file that states its error's walk (version 5) raises the external force's walk to
// it: the estimate moves, and config.yaml says what ran.
TEST_F(HdvioRun, WeightFileWalkRaisesTheForceWalk) {
  learned::TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.05);
  const std::string without = (dir_ / "walk_none.tcn").string();
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, without, "hdvio_run test");
  info.force_walk = 0.5;
  const std::string with = (dir_ / "walk.tcn").string();
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, with, "hdvio_run test");
  const auto tight = hdvioOutput("w_none", without, kFloor);
  const auto loose = hdvioOutput("w_file", with, kFloor);
  ASSERT_GT(tight.size(), 40u);
  ASSERT_EQ(tight.size(), loose.size());
  double moved = 0.0;
  for (std::size_t k = 0; k < tight.size(); ++k) moved = std::max(moved, (loose[k].second - tight[k].second).norm());
  EXPECT_GT(moved, 1e-4);
  const YAML::Node ran = YAML::LoadFile((dir_ / "o_w_file" / "config.yaml").string())["backend"];
  EXPECT_EQ(ran["force_random_walk"].as<double>(), 0.5);
  EXPECT_EQ(YAML::LoadFile((dir_ / "o_w_none" / "config.yaml").string())["backend"]["force_random_walk"].as<double>(),
            0.02);
}

// A weight file that states its training envelope (version 7): inside it the run is the run
// without one, byte for byte; a flight outside it gets the loose walk (the estimate moves), and
// config.yaml says what ran.
TEST_F(HdvioRun, FlightOutsideTheModelsEnvelopeLoosensTheForceWalk) {
  learned::TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.05);
  const auto weights = [&](const std::string& name, double speed_max) {
    info.envelope.speed_max = speed_max;
    info.envelope.rate_max = 100.0;
    info.envelope.thrust_min = 0.0;
    info.envelope.thrust_max = 100.0;
    const std::string path = (dir_ / name).string();
    learned::saveTcnFile(learned::testing::deterministicTcn(), info, path, "hdvio_run test");
    return path;
  };
  const std::string none = (dir_ / "env_none.tcn").string();
  learned::saveTcnFile(learned::testing::deterministicTcn(), info, none, "hdvio_run test");  // no envelope
  const auto plain = hdvioOutput("e_none", none, kFloor);
  const auto inside = hdvioOutput("e_inside", weights("env_wide.tcn", 100.0), kFloor);
  const auto outside = hdvioOutput("e_outside", weights("env_slow.tcn", 0.05), kFloor);
  ASSERT_GT(plain.size(), 40u);
  ASSERT_EQ(plain.size(), inside.size());
  ASSERT_EQ(plain.size(), outside.size());
  double moved = 0.0;
  for (std::size_t k = 0; k < plain.size(); ++k) {
    EXPECT_EQ(inside[k].second, plain[k].second) << k;
    moved = std::max(moved, (outside[k].second - plain[k].second).norm());
  }
  EXPECT_GT(moved, 1e-3);
  const YAML::Node ran = YAML::LoadFile((dir_ / "o_e_outside" / "config.yaml").string())["backend"];
  EXPECT_EQ(ran["model_speed_max"].as<double>(), 0.05);
  EXPECT_EQ(ran["model_thrust_range"][1].as<double>(), 100.0);
  EXPECT_EQ(ran["force_walk_outside_model"].as<double>(), 5.0);
  EXPECT_FALSE(YAML::LoadFile((dir_ / "o_e_none" / "config.yaml").string())["backend"]["model_speed_max"]);
}

TEST_F(HdvioRun, BadExperimentsAndMissingSensorsAreClearErrors) {
  const std::string seq = (dir_ / "seq").string();
  const std::string typo = writeConfig("typo.yaml", "method: vio\nbackend:\n  num_keyframe: 10\n");
  Outcome o = run("--config " + typo + " --dataset " + seq + " --out " + (dir_ / "o1").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("typo.yaml:3: key 'backend.num_keyframe': unknown key"), std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o1"));

  const std::string bad_method = writeConfig("m.yaml", "method: slam\n");
  o = run("--config " + bad_method + " --dataset " + seq + " --out " + (dir_ / "o2").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("'slam' is not one of"), std::string::npos) << o.output;

  // hdvio needs thrust: a copy of the sequence without thrust0 and rotor0.
  const fs::path no_thrust = dir_ / "no_thrust";
  fs::copy(seq, no_thrust, fs::copy_options::recursive);
  fs::remove_all(no_thrust / "mav0" / "thrust0");
  fs::remove_all(no_thrust / "mav0" / "rotor0");
  const std::string hdvio = writeConfig("h.yaml", "method: hdvio\n");
  o = run("--config " + hdvio + " --dataset " + no_thrust.string() + " --out " + (dir_ / "o3").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("needs thrust"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(dir_ / "o3"));

  // Never deletes a folder it did not write.
  fs::create_directories(dir_ / "precious");
  std::ofstream(dir_ / "precious" / "notes.txt") << "keep";
  o = run("--config " + hdvio + " --dataset " + seq + " --out " + (dir_ / "precious").string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_TRUE(fs::exists(dir_ / "precious" / "notes.txt"));
}

}  // namespace
}  // namespace hdvio
