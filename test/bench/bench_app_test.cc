// hdvio_bench end to end: bad matrices exit 2 with one error line, --emit-jobs writes one
// command per line, and a tiny matrix (ci_tiny simulated, vio + vimo, --jobs 2) produces a table
// whose numbers are the ones hdvio_eval computes for the same folders.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "bench_test_helpers.h"
#include "hdvio/bench/aggregate.h"

namespace {
namespace fs = std::filesystem;

using namespace hdvio::test;  // bench, runShell, readFile, jsonNumber (bench_test_helpers.h)
using Outcome = CommandOutcome;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) out.push_back(line);
  return out;
}

const std::string kSource = HDVIO_SOURCE_DIR;

class BenchApp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = freshTempDir("hdvio_bench_app_");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path BenchApp::dir_;

TEST_F(BenchApp, StageTotalsLeaveOutTheFrontendsParts) {
  // A run on images lists the frontend's parts under it; the runtime counts each second once.
  const fs::path file = dir_ / "timing_stages.csv";
  std::ofstream(file) << "stage,total [s],calls,mean [ms],p50 [ms],p90 [ms],max [ms]\n"
                      << "image_loading,0.5,10,50,,,\n"
                      << "frontend,2,10,200,150,300,400\n"
                      << "frontend/alignment,0.75,10,75,70,90,100\n"
                      << "frontend/depth_filter,1,10,100,90,120,150\n"
                      << "backend,3,10,300,250,400,500\n";
  const auto stages = hdvio::bench::readStages(file.string());
  ASSERT_EQ(stages.size(), 3u);
  EXPECT_EQ(stages[0].first, "image_loading");
  EXPECT_EQ(stages[1].first, "frontend");
  EXPECT_EQ(stages[2].first, "backend");
  EXPECT_DOUBLE_EQ(stages[0].second + stages[1].second + stages[2].second, 5.5);
}

// results.json parses as JSON: missing numbers are null, an error's newlines and control
// characters are escaped (not dropped), invalid UTF-8 becomes U+FFFD instead of raw bytes.
TEST_F(BenchApp, ResultsJsonHasNullsAndEscapedText) {
  hdvio::bench::Matrix matrix;
  matrix.file = "matrix \"q\".yaml";
  hdvio::bench::RunMetrics a;
  a.job.sequence = "s";
  a.job.experiment = "vio";
  a.job.seed = 3;
  a.status = "failed";
  a.error = "line 1\nline 2\t\x01 \xff";
  a.ate_t_m = 0.1;
  a.ate_r_deg = INFINITY;
  a.matched = 7;
  a.stages = {{"frontend", 2.0}, {"backend", NAN}};
  hdvio::bench::RunMetrics b;
  b.job.sequence = "s";
  b.job.experiment = "vimo";
  const fs::path out = dir_ / "json";
  hdvio::bench::writeBenchReport(matrix, {a, b}, out.string());
  const nlohmann::json j = nlohmann::json::parse(readFile(out / "results.json"));
  EXPECT_EQ(j["matrix"], matrix.file);
  EXPECT_EQ(j["alignment"], "posyaw");
  ASSERT_EQ(j["runs"].size(), 2u);
  const nlohmann::json& r = j["runs"][0];
  EXPECT_EQ(r["experiment"], "vio");
  EXPECT_TRUE(r["seed"].is_number_integer());
  EXPECT_EQ(r["seed"], 3);
  EXPECT_EQ(r["ate_t_m"].get<double>(), 0.1);  // round-trips exactly
  EXPECT_TRUE(r["ate_r_deg"].is_null());       // inf
  EXPECT_TRUE(r["rpe_t_m"].is_null());         // NaN
  EXPECT_EQ(r["matched"], 7);
  EXPECT_EQ(r["stages"]["frontend"].get<double>(), 2.0);
  EXPECT_TRUE(r["stages"]["backend"].is_null());
  EXPECT_EQ(r["error"], "line 1\nline 2\t\x01 \xef\xbf\xbd");
  EXPECT_EQ(r["peer"], false);
  EXPECT_TRUE(j["runs"][1]["seed"].is_null());
  EXPECT_EQ(j["runs"][1]["status"], "missing");
}

TEST_F(BenchApp, BadMatrixIsOneErrorLineAndExitCode2) {
  const fs::path m = dir_ / "bad.yaml";
  std::ofstream(m) << "experiments:\n  - {name: vio, config: " << kSource
                   << "/config/experiments/vio.yaml}\nsequences:\n  - {name: s, dataset: /no/such/folder}\n";
  const Outcome o = bench("--matrix " + m.string() + " --out " + (dir_ / "bad_out").string());
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_EQ(o.output, "error: " + m.string() +
                          ":4: key 'sequences[0].dataset': no such file or folder: /no/such/folder\n");
  EXPECT_FALSE(fs::exists(dir_ / "bad_out"));
  const Outcome missing = bench("--matrix " + (dir_ / "absent.yaml").string() + " --out x");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_EQ(lines(missing.output).size(), 1u) << missing.output;
}

TEST_F(BenchApp, EmitJobsWritesOneCommandPerLine) {
  const std::string out = (dir_ / "emit").string();
  const Outcome o = bench("--matrix " + kSource + "/config/bench/sim_drag.yaml --out " + out +
                          " --emit-jobs - --only random_v5");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  int sims = 0, runs = 0, aggregate = 0;
  for (const std::string& l : lines(o.output)) {
    if (l.empty() || l[0] == '#') continue;
    if (l.find("hdvio_sim --config " + kSource + "/config/sim/bench_random_v5") != std::string::npos) {
      EXPECT_NE(l.find(" --no_images "), std::string::npos) << l;
      ++sims;
    } else if (l.find("hdvio_run --config " + kSource + "/config/experiments/") != std::string::npos) {
      EXPECT_NE(l.find(" --dataset " + out + "/sequences/random_v5"), std::string::npos) << l;
      EXPECT_NE(l.find("/result --plots=false > " + out + "/runs/random_v5"), std::string::npos) << l;
      ++runs;
    } else if (l.find("hdvio_bench --matrix ") != std::string::npos) {
      EXPECT_NE(l.find("--aggregate_only"), std::string::npos) << l;
      ++aggregate;
    } else {
      ADD_FAILURE() << "unexpected line: " << l;
    }
  }
  EXPECT_EQ(sims, 2);       // random_v5 and random_v5_wind
  EXPECT_EQ(runs, 10);      // 5 methods on each
  EXPECT_EQ(aggregate, 1);  // last
  EXPECT_FALSE(fs::exists(fs::path(out) / "table.md"));
}

TEST_F(BenchApp, TinyMatrixTableMatchesHdvioEval) {
  const fs::path out = dir_ / "tiny";
  const Outcome o = bench("--matrix " + kSource + "/config/bench/ci_tiny.yaml --out " +
                          out.string() + " --jobs 2");
  ASSERT_EQ(o.exit_code, 0) << o.output;
  for (const char* f : {"table.md", "results.csv", "results.json", "evaluation/ci_tiny/metrics.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const std::string table = readFile(out / "table.md");
  EXPECT_NE(table.find("| sequence | vio | vimo |"), std::string::npos) << table;
  EXPECT_NE(table.find("Force RMSE"), std::string::npos) << table;  // vimo estimates a force

  const std::string results = readFile(out / "results.json");
  for (const std::string method : {"vio", "vimo"}) {
    const fs::path result = out / "runs" / "ci_tiny" / method / "result";
    const fs::path eval_out = dir_ / ("eval_" + method);
    const Outcome e = runShell(std::string(HDVIO_EVAL_BINARY) + " --gt " +
                               (out / "sequences" / "ci_tiny").string() + " --est " + method + "=" +
                               result.string() + " --out " + eval_out.string());
    ASSERT_EQ(e.exit_code, 0) << e.output;
    const std::string metrics = readFile(eval_out / "metrics.json");
    const std::size_t run = results.find("\"experiment\": \"" + method + "\"");
    ASSERT_NE(run, std::string::npos);
    EXPECT_NE(results.find("\"status\": \"ok\"", run), std::string::npos);
    const double ate_eval = jsonNumber(metrics, "rmse", metrics.find("ate_translation_m"));
    const double rot_eval = jsonNumber(metrics, "rmse", metrics.find("ate_rotation_deg"));
    EXPECT_GT(ate_eval, 0.0);
    EXPECT_LT(ate_eval, 0.5);  // a working estimator on a 3 s flight
    EXPECT_NEAR(jsonNumber(results, "ate_t_m", run), ate_eval, 1e-12 * ate_eval);
    EXPECT_NEAR(jsonNumber(results, "ate_r_deg", run), rot_eval, 1e-12 * rot_eval);
    // hdvio_run's own evaluation (result/evaluation/) agrees as well.
    const std::string own = readFile(result / "evaluation" / "metrics.json");
    EXPECT_NEAR(jsonNumber(own, "rmse", own.find("ate_translation_m")), ate_eval, 1e-12 * ate_eval);
    EXPECT_GT(jsonNumber(results, "runtime_s", run), 0.0);
    EXPECT_GT(jsonNumber(results, "realtime_factor", run), 0.0);
    if (method == "vimo") {
      const double f_eval = jsonNumber(metrics, "rmse", metrics.find("force_total_m_s2"));
      EXPECT_NEAR(jsonNumber(results, "force_total_rmse_m_s2", run), f_eval, 1e-12 * f_eval);
    }
  }

  // A second invocation skips completed runs; a broken experiment is a failed cell, not a crash.
  const fs::path broken = dir_ / "broken.yaml";
  std::ofstream(broken) << "method: vio\nbackend: {num_keyframez: 3}\n";
  const fs::path m2 = dir_ / "matrix2.yaml";
  std::ofstream(m2) << "experiments:\n  - {name: vio, config: " << kSource
                    << "/config/experiments/vio.yaml}\n  - {name: broken, config: " << broken.string()
                    << "}\nsequences:\n  - {name: ci_tiny, sim: " << kSource
                    << "/config/sim/ci_tiny.yaml, images: false}\nmetrics: {plots: false}\n";
  const Outcome again = bench("--matrix " + m2.string() + " --out " + out.string());
  EXPECT_EQ(again.exit_code, 1) << again.output;
  EXPECT_NE(again.output.find("1 runs to do, 1 already complete"), std::string::npos) << again.output;
  const std::string table2 = readFile(out / "table.md");
  EXPECT_NE(table2.find("| ci_tiny | " ), std::string::npos) << table2;
  EXPECT_NE(table2.find("failed: error: "), std::string::npos) << table2;
  EXPECT_NE(table2.find("num_keyframez"), std::string::npos) << table2;
}

}  // namespace
