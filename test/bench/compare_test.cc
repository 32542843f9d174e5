// hdvio_bench --compare: seed means of the runs both outputs have, seeds that got worse, sums
// per experiment; a missing folder or an unknown metric is one error, exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench_test_helpers.h"
#include "hdvio/bench/compare.h"
#include "hdvio/core/error.h"

namespace {
namespace fs = std::filesystem;
using hdvio::bench::compareRuns;
using hdvio::bench::readRunValues;
using Json = nlohmann::json;

Json run(const std::string& sequence, const std::string& experiment, int seed, double ate,
         const std::string& status = "ok") {
  return {{"sequence", sequence}, {"experiment", experiment}, {"seed", seed},
          {"status", status},     {"ate_t_m", ate},             {"rpe_t_m", nullptr}};
}

fs::path writeOutput(const std::string& name, const Json& runs) {
  const fs::path dir = hdvio::test::freshTempDir("hdvio_compare_" + name);
  std::ofstream(dir / "results.json") << Json{{"matrix", "m.yaml"}, {"runs", runs}}.dump();
  return dir;
}

TEST(BenchCompare, SeedMeansOfTheRunsBothHave) {
  // Before: seeds 1-3 on two flights; after: seeds 1-2 and a seed 4 the other lacks, one
  // failed run and a second experiment only 'after' has.
  const fs::path before = writeOutput(
      "before", Json::array({run("a", "vio", 1, 0.10), run("a", "vio", 2, 0.20),
                             run("a", "vio", 3, 0.30), run("b", "vio", 1, 0.40),
                             run("b", "vio", 2, 0.50)}));
  const fs::path after = writeOutput(
      "after", Json::array({run("a", "vio", 1, 0.05), run("a", "vio", 2, 0.30),
                            run("a", "vio", 4, 9.0), run("b", "vio", 1, 0.0, "failed"),
                            run("b", "vio", 2, 0.45), run("a", "hdvio", 1, 0.1)}));
  const auto c = compareRuns(readRunValues(before.string(), "ate_t_m"),
                             readRunValues(after.string(), "ate_t_m"));
  ASSERT_EQ(c.cells.size(), 2u);
  EXPECT_EQ(c.cells[0].sequence, "a");
  EXPECT_EQ(c.cells[0].seeds, 2);
  EXPECT_NEAR(c.cells[0].before, 0.15, 1e-12);
  EXPECT_NEAR(c.cells[0].after, 0.175, 1e-12);
  EXPECT_EQ(c.cells[0].worse_seeds, 1);
  EXPECT_EQ(c.cells[1].sequence, "b");
  EXPECT_EQ(c.cells[1].seeds, 1);  // the failed seed 1 is left out on both sides
  EXPECT_NEAR(c.cells[1].before, 0.50, 1e-12);
  EXPECT_NEAR(c.cells[1].after, 0.45, 1e-12);
  ASSERT_EQ(c.experiments.size(), 1u);
  EXPECT_NEAR(c.experiments[0].before_sum, 0.65, 1e-12);
  EXPECT_NEAR(c.experiments[0].after_sum, 0.625, 1e-12);
  EXPECT_EQ(c.experiments[0].better_cells, 1);

  const auto o = hdvio::test::bench("--compare " + before.string() + " --out " + after.string());
  EXPECT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("| vio | b | 1 | 0.5000 | 0.4500 | -10.0 % | 0 of 1 |"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("| vio | 0.6500 | 0.6250 | -3.8 % | 1 of 2 |"), std::string::npos)
      << o.output;
}

TEST(BenchCompare, BadInputIsOneErrorWithTheFile) {
  const fs::path good = writeOutput("good", Json::array({run("a", "vio", 1, 0.1)}));
  EXPECT_THROW(readRunValues(good.string(), "no_such_metric"), hdvio::InputError);
  EXPECT_THROW(readRunValues(good.string(), "experiment"), hdvio::InputError);  // not a number
  const fs::path missing = good / "nothing_here";
  auto o = hdvio::test::bench("--compare " + missing.string() + " --out " + good.string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find((missing / "results.json").string()), std::string::npos) << o.output;
  o = hdvio::test::bench("--compare " + good.string() + " --out " + good.string() +
                         " --matrix config/bench/ci_tiny.yaml");
  EXPECT_EQ(o.exit_code, 2);  // comparing runs nothing
  EXPECT_NE(o.output.find("--matrix"), std::string::npos) << o.output;
  const fs::path broken = hdvio::test::freshTempDir("hdvio_compare_broken");
  std::ofstream(broken / "results.json") << "{\"runs\": [";
  o = hdvio::test::bench("--compare " + good.string() + " --out " + broken.string());
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.output.find("malformed JSON"), std::string::npos) << o.output;
}

}  // namespace
