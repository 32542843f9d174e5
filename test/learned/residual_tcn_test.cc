// The residual (temporal-block) TCN of the IMO displacement network: architecture, a tiny
// network checked by hand, windowed = sequence inference, libtorch parity fixture.
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "deterministic_tcn.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {
namespace {

double gelu(double v) { return 0.5 * v * (1.0 + std::erf(v / std::sqrt(2.0))); }

TEST(ResidualTcn, ImoArchitecture) {
  const TcnArchitecture a = TcnArchitecture::imo();
  EXPECT_TRUE(a.residual);
  EXPECT_EQ(a.layers.size(), 7u);
  EXPECT_EQ(a.convolutionCount(), 14);
  EXPECT_EQ(a.window, 50);
  EXPECT_EQ(a.receptiveField(), 1 + 2 * (8 + 8 + 4 + 1 + 1 + 1 + 1));  // 49 <= 50
  const Tcn tcn = testing::deterministicResidualTcn();
  // convs: 6->64 (k2), 64->64 x7 (k2), 64->128, 128->128 x5; skips 6->64, 64->128; head.
  const std::size_t expected = (12 * 64 + 64) + 7 * (128 * 64 + 64) + (128 * 128 + 128) +
                               5 * (256 * 128 + 128) + (6 * 64 + 64) + (64 * 128 + 128) + (128 * 3 + 3);
  EXPECT_EQ(tcn.parameterCount(), expected);
}

// One identity-skip block (width 6, dilation 1) and one block that narrows to 3 channels
// through its 1x1 skip; every weight is 0 or 1, so the output follows by hand:
//   h[t] = GELU(x[t-1] + x[t]), y1[t] = GELU(h[t]) + x[t],
//   y2[t] = GELU(0) + S y1[t] + (1, 2, 3) = y1[t](0..2) + (1, 2, 3), output = y2[last].
TEST(ResidualTcn, TinyNetworkByHand) {
  TcnArchitecture a;
  a.residual = true;
  a.window = 5;  // receptive field 1 + 2 * (1 + 1) = 5
  a.layers = {{6, 1}, {3, 1}};
  TcnWeights w;
  w.input_mean = VectorXf::Zero(6);
  w.input_std = VectorXf::Constant(6, 2.0f);  // inputs are halved first
  MatrixXf both(6, 12), current(6, 12);
  both << MatrixXf::Identity(6, 6), MatrixXf::Identity(6, 6);
  current << MatrixXf::Zero(6, 6), MatrixXf::Identity(6, 6);
  w.conv.push_back({both, VectorXf::Zero(6)});
  w.conv.push_back({current, VectorXf::Zero(6)});
  w.skip.push_back({});
  w.conv.push_back({MatrixXf::Zero(3, 12), VectorXf::Zero(3)});
  w.conv.push_back({MatrixXf::Zero(3, 6), VectorXf::Zero(3)});
  MatrixXf s = MatrixXf::Zero(3, 6);
  s.leftCols(3).setIdentity();
  w.skip.push_back({s, Eigen::Vector3f(1, 2, 3)});
  w.head_weight = MatrixXf::Identity(3, 3);
  w.head_bias = VectorXf::Zero(3);
  const Tcn tcn(a, w);

  MatrixXf x(6, 5);
  for (int c = 0; c < 6; ++c)
    for (int t = 0; t < 5; ++t) x(c, t) = static_cast<float>(0.3 * (c + 1) - 0.25 * t);
  const TcnOutput out = tcn.predictWindow(x);
  for (int c = 0; c < 3; ++c) {
    const double prev = x(c, 3) / 2.0, now = x(c, 4) / 2.0;
    const double expected = gelu(gelu(prev + now)) + now + (c + 1);
    EXPECT_NEAR(out.force(c), expected, 1e-6) << c;
  }
  EXPECT_NEAR(tcn.forwardSequence(x)(0, 4), out.force(0), 1e-6);
}

TEST(ResidualTcn, WindowPredictionEqualsLastStepOfSequence) {
  const Tcn tcn = testing::deterministicResidualTcn();
  const MatrixXf x = testing::deterministicInputs(90);
  const MatrixXf seq = tcn.forwardSequence(x);
  for (int end : {49, 63, 89}) {
    const TcnOutput out = tcn.predictWindow(x.middleCols(end - 49, 50));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(out.force(i), seq(i, end), 2e-5) << end;
  }
}

TEST(ResidualTcn, OutputIgnoresSamplesBeforeTheReceptiveField) {
  const Tcn tcn = testing::deterministicResidualTcn();
  MatrixXf x = testing::deterministicInputs(80);
  const MatrixXf before = tcn.forwardSequence(x);
  x.leftCols(10).setConstant(50.0f);  // steps 0..9: outputs from 9 + 48 = 57 on must not change
  const MatrixXf after = tcn.forwardSequence(x);
  EXPECT_GT((before.col(56) - after.col(56)).norm(), 1e-4);  // the receptive field is exactly 49
  for (int t = 58; t < 80; ++t) EXPECT_LT((before.col(t) - after.col(t)).norm(), 1e-6) << t;
}

// CI without libtorch: the Eigen residual network against libtorch's outputs stored by
// `hdvio_make_tcn_parity_fixture residual` (same padding: F.pad((k-1) d, 0) before each conv).
TEST(ResidualTcn, MatchesLibtorchReferenceOutputs) {
  std::ifstream in(std::string(HDVIO_SOURCE_DIR) + "/test/learned/data/tcn_residual_parity_reference.txt");
  ASSERT_TRUE(in.good()) << "missing test/learned/data/tcn_residual_parity_reference.txt";
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    rows.emplace_back();
    for (double v; ss >> v;) rows.back().push_back(v);
    ASSERT_EQ(rows.back().size(), 3u);
  }
  ASSERT_EQ(static_cast<int>(rows.size()), testing::kResidualParitySteps);
  const Tcn tcn = testing::deterministicResidualTcn();
  const MatrixXf x = testing::deterministicInputs(testing::kResidualParitySteps);
  const MatrixXf out = tcn.forwardSequence(x);
  double max_err = 0.0, max_abs = 0.0;
  for (int t = 0; t < testing::kResidualParitySteps; ++t) {
    for (int c = 0; c < 3; ++c) {
      max_err = std::max(max_err, std::abs(out(c, t) - rows[t][c]));
      max_abs = std::max(max_abs, std::abs(rows[t][c]));
    }
  }
  EXPECT_LT(max_err, 2e-5) << "largest output magnitude " << max_abs;
  EXPECT_GT(max_abs, 0.1);
  // The deployed path (only what the last output needs) on the fixture's last window.
  const TcnOutput last = tcn.predictWindow(x.rightCols(50));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(last.force(c), rows.back()[c], 2e-5);
}

TEST(ResidualTcn, RejectsInconsistentWeights) {
  const Tcn good = testing::deterministicResidualTcn();
  TcnWeights w = good.weights();
  w.skip[0] = {};  // 6 -> 64 needs a projection
  EXPECT_THROW(Tcn(good.architecture(), w), std::invalid_argument);
  w = good.weights();
  w.skip[1] = w.skip[0];  // 64 -> 64 must be the identity
  EXPECT_THROW(Tcn(good.architecture(), w), std::invalid_argument);
  w = good.weights();
  w.conv.pop_back();
  EXPECT_THROW(Tcn(good.architecture(), w), std::invalid_argument);
  TcnArchitecture a = good.architecture();
  a.window = 48;  // < receptive field 49
  EXPECT_THROW(a.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
