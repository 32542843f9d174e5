#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "deterministic_tcn.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {
namespace {

TEST(Tcn, PaperArchitectureHasReceptiveFieldOfTheWindow) {
  const TcnArchitecture a = TcnArchitecture::paper();
  EXPECT_EQ(a.layers.size(), 7u);
  EXPECT_EQ(a.receptiveField(), 10);
  EXPECT_EQ(a.window, 10);
  int n64 = 0, n128 = 0;
  for (const auto& l : a.layers) (l.out_channels == 64 ? n64 : n128) += 1;
  EXPECT_EQ(n64, 4);
  EXPECT_EQ(n128, 3);
}

TEST(Tcn, GeluMatchesDefinition) {
  MatrixXf x(1, 7);
  x << -4.0f, -1.5f, -0.3f, 0.0f, 0.2f, 1.0f, 3.5f;
  const MatrixXf in = x;
  geluInPlace(&x);
  for (int i = 0; i < 7; ++i) {
    const double v = in(0, i);
    EXPECT_NEAR(x(0, i), 0.5 * v * (1.0 + std::erf(v / std::sqrt(2.0))), 2e-6) << v;
  }
}

TEST(Tcn, WindowPredictionEqualsLastStepOfSequence) {
  const Tcn tcn = testing::deterministicTcn();
  const MatrixXf x = testing::deterministicInputs(40);
  const MatrixXf seq = tcn.forwardSequence(x);
  for (int end : {9, 20, 39}) {
    const TcnOutput out = tcn.predictWindow(x.middleCols(end - 9, 10));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(out.force(i), seq(i, end), 1e-5) << end;
      EXPECT_NEAR(out.log_variance(i), seq(3 + i, end), 1e-5) << end;
    }
  }
}

TEST(Tcn, OutputIgnoresSamplesBeforeTheReceptiveField) {
  const Tcn tcn = testing::deterministicTcn();
  MatrixXf x = testing::deterministicInputs(30);
  const MatrixXf before = tcn.forwardSequence(x);
  x.leftCols(10).setConstant(50.0f);  // steps 0..9 changed: outputs from step 19 on must not
  const MatrixXf after = tcn.forwardSequence(x);
  EXPECT_GT((before.col(15) - after.col(15)).norm(), 1e-3);  // sanity: earlier ones do change
  for (int t = 19; t < 30; ++t) EXPECT_LT((before.col(t) - after.col(t)).norm(), 1e-6) << t;
}

// CI without libtorch: the Eigen network against libtorch numbers stored by
// hdvio_make_tcn_parity_fixture (deterministic weights and inputs), to 1e-5.
TEST(Tcn, MatchesLibtorchReferenceOutputs) {
  std::ifstream in(std::string(HDVIO_SOURCE_DIR) + "/test/learned/data/tcn_parity_reference.txt");
  ASSERT_TRUE(in.good()) << "missing test/learned/data/tcn_parity_reference.txt";
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    rows.emplace_back();
    for (double v; ss >> v;) rows.back().push_back(v);
    ASSERT_EQ(rows.back().size(), 6u);
  }
  ASSERT_EQ(static_cast<int>(rows.size()), testing::kParitySteps);
  const Tcn tcn = testing::deterministicTcn();
  const MatrixXf out = tcn.forwardSequence(testing::deterministicInputs(testing::kParitySteps));
  double max_err = 0.0, max_abs = 0.0;
  for (int t = 0; t < testing::kParitySteps; ++t) {
    for (int c = 0; c < 6; ++c) {
      max_err = std::max(max_err, std::abs(out(c, t) - rows[t][c]));
      max_abs = std::max(max_abs, std::abs(rows[t][c]));
    }
  }
  EXPECT_LT(max_err, 1e-5) << "largest output magnitude " << max_abs;
  EXPECT_GT(max_abs, 0.1);  // the reference is not trivially zero
}

TEST(Tcn, RejectsInconsistentWeights) {
  TcnArchitecture a = TcnArchitecture::paper();
  TcnWeights w = testing::deterministicTcn().weights();
  w.logvar_weight.resize(0, 0);
  w.logvar_bias.resize(0);
  EXPECT_NO_THROW(Tcn(a, w));
  TcnWeights bad = w;
  bad.conv[3].weight(0, 0) = std::nanf("");
  EXPECT_THROW(Tcn(a, bad), std::invalid_argument);
  bad = w;
  bad.conv[2].bias.resize(3);
  EXPECT_THROW(Tcn(a, bad), std::invalid_argument);
  a.window = 8;  // shorter than the receptive field
  EXPECT_THROW(Tcn(a, w), std::invalid_argument);
}

TEST(Tcn, PredictWindowRejectsWrongShape) {
  const Tcn tcn = testing::deterministicTcn();
  EXPECT_THROW(tcn.predictWindow(MatrixXf::Zero(6, 9)), std::invalid_argument);
  EXPECT_THROW(tcn.predictWindow(MatrixXf::Zero(5, 10)), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
