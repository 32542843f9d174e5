// libtorch-only checks: Eigen inference against libtorch on trained-like random weights,
// and a tiny training run that must reduce the Eq. 7 loss.
#include <cmath>

#include <gtest/gtest.h>

#include "hdvio/core/sequence.h"
#include "hdvio/learned/torch/tcn_module.h"
#include "hdvio/learned/torch/trainer.h"

namespace hdvio::learned {
namespace {

TEST(TorchParity, EigenMatchesLibtorchForRandomWeights) {
  torch::manual_seed(11);
  TcnModule module(TcnArchitecture::paper(true));
  torch::NoGradGuard no_grad;
  module->setNormalization(torch::tensor({0.1f, -0.2f, 9.5f, 0.0f, 0.1f, -0.1f}),
                           torch::tensor({1.5f, 1.2f, 2.0f, 0.8f, 0.9f, 0.5f}));
  const torch::Tensor x = torch::randn({1, 6, 40}) * 2.0 + torch::tensor({0.f, 0.f, 9.8f, 0.f, 0.f, 0.f}).view({1, 6, 1});
  const torch::Tensor ref = module->forward(x)[0].contiguous();
  const Tcn tcn = exportTcn(module);
  MatrixXf in(6, 40);
  for (int c = 0; c < 6; ++c)
    for (int t = 0; t < 40; ++t) in(c, t) = x[0][c][t].item<float>();
  const MatrixXf out = tcn.forwardSequence(in);
  double max_err = 0.0;
  for (int c = 0; c < 6; ++c)
    for (int t = 0; t < 40; ++t) max_err = std::max(max_err, std::abs(out(c, t) - ref[c][t].item<double>()));
  EXPECT_LT(max_err, 1e-5);
  // Import -> same outputs again.
  TcnModule back = importTcn(tcn);
  EXPECT_LT((back->forward(x) - module->forward(x)).abs().max().item<double>(), 1e-6);
}

// 20 s circle-like flight at 100 Hz whose residual force is a fixed linear map of the thrust.
FlightSamples syntheticFlight(double phase) {
  FlightSamples f;
  f.name = "synthetic";
  f.rate_hz = 100.0;
  Mat3 M = Mat3::Zero();
  M(0, 2) = -0.03;
  M(1, 2) = 0.02;
  M(2, 2) = -0.08;
  for (int k = 0; k < 2000; ++k) {
    const double t = k / 100.0 + phase;
    const Vec3 p(4 * std::sin(0.8 * t), 3 * std::cos(0.6 * t), 1 + 0.5 * std::sin(1.3 * t));
    const Vec3 v(3.2 * std::cos(0.8 * t), -1.8 * std::sin(0.6 * t), 0.65 * std::cos(1.3 * t));
    const Vec3 a(-2.56 * std::sin(0.8 * t), -1.08 * std::cos(0.6 * t), -0.845 * std::sin(1.3 * t));
    const Vec3 phi(0.15 * std::sin(0.8 * t), 0.1 * std::cos(0.6 * t), 0.5 * t);
    const Quat q = quatExp(phi);
    const Vec3 specific = q.conjugate() * (a - gravityWorld());
    f.t.push_back(fromSeconds(t));
    f.p_W.push_back(p);
    f.v_W.push_back(v);
    f.q_WB.push_back(q);
    f.force.push_back(specific);
    f.thrust.push_back((Mat3::Identity() + M).inverse() * specific);  // thrust + M thrust = specific
    f.gyro.push_back(Vec3(0.12 * std::cos(0.8 * t), -0.06 * std::sin(0.6 * t), 0.5));
  }
  return f;
}

// The paper's layout at a quarter of the widths: trains in seconds.
TcnArchitecture tinyArchitecture() {
  TcnArchitecture a;
  a.layers = {{16, 1}, {16, 1}, {16, 2}, {16, 2}, {32, 1}, {32, 1}, {32, 1}};
  return a;
}

// Options of the short test runs.
TrainOptions shortRun(int epochs, int stride) {
  TrainOptions o;
  o.max_epochs = epochs;
  o.patience = epochs;
  o.learning_rate = 1e-3;
  o.stride_samples = stride;
  o.seed = 3;
  return o;
}

TEST(TorchTraining, TinyRunReducesValidationLoss) {
  TcnArchitecture a = tinyArchitecture();
  const TrainOptions o = shortRun(8, 4);
  Trainer trainer(a, o);
  std::ostringstream log;
  const TrainingResult r = trainer.train({syntheticFlight(0.0)}, {syntheticFlight(40.0)}, log);
  ASSERT_GE(r.history.size(), 2u);
  const double before = r.history.front().validation_loss;
  const double after = r.history[r.best_epoch].validation_loss;
  EXPECT_GT(before, 0.05) << log.str();  // the thrust alone leaves a clear residual
  EXPECT_LT(after, 0.3 * before) << log.str();
  EXPECT_GT(r.best_epoch, 0);
  EXPECT_EQ(r.best.architecture().layers.size(), 7u);
}

TEST(TorchTraining, VarianceHeadTrainsToFiniteVariances) {
  TcnArchitecture a = tinyArchitecture();
  a.variance_head = true;
  TrainOptions o;
  o.max_epochs = 4;
  o.learning_rate = 1e-3;
  o.stride_samples = 8;
  Trainer trainer(a, o);
  std::ostringstream log;
  const TrainingResult r = trainer.train({syntheticFlight(0.0)}, {syntheticFlight(40.0)}, log);
  EXPECT_GT(r.best_epoch, 0) << log.str();
  EXPECT_TRUE(std::isfinite(r.history.back().train_loss));
  ASSERT_TRUE(r.best.architecture().variance_head);
  const FlightSamples f = syntheticFlight(80.0);
  MatrixXf x(6, 50);
  for (int k = 0; k < 50; ++k) {
    x.col(k).head<3>() = f.thrust[k].cast<float>();
    x.col(k).tail<3>() = f.gyro[k].cast<float>();
  }
  const MatrixXf out = r.best.forwardSequence(x);
  EXPECT_TRUE(out.allFinite());
  EXPECT_EQ(out.rows(), 6);
}

TEST(TorchTraining, SegmentsRemoveTheThrustPart) {
  // With the exact thrust = specific force (no residual), alpha/beta targets are near zero.
  FlightSamples f = syntheticFlight(0.0);
  f.thrust = f.force;
  TrainOptions o;
  const SegmentSet s = buildSegments({f}, 10, o);
  EXPECT_GT(s.size(), 100);
  EXPECT_LT(s.beta_rest.abs().max().item<double>(), 2e-3);
  EXPECT_LT(s.alpha_rest.abs().max().item<double>(), 2e-4);
}

TEST(TorchTraining, SegmentsRemoveTheDragLawAtTheTrueVelocity) {
  // Thrust = specific force minus a drag law at the true body velocity: with that law in the
  // options the targets are near zero again, without it they hold the drag.
  FlightSamples f = syntheticFlight(0.0);
  TrainOptions o;
  o.drag.linear = Vec3(0.3, 0.25, 0.05);
  o.drag.quadratic = Vec3(0.01, 0.02, 0.01);
  for (std::size_t k = 0; k < f.size(); ++k)
    f.thrust[k] = f.force[k] - o.drag.force(f.q_WB[k].conjugate() * f.v_W[k], f.thrust[k].norm());
  const SegmentSet with = buildSegments({f}, 10, o);
  EXPECT_LT(with.beta_rest.abs().max().item<double>(), 2e-3);
  EXPECT_LT(with.alpha_rest.abs().max().item<double>(), 2e-4);
  const SegmentSet without = buildSegments({f}, 10, TrainOptions());
  EXPECT_GT(without.beta_rest.abs().max().item<double>(), 0.05);
}

}  // namespace
}  // namespace hdvio::learned
