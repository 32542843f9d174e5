// libtorch-only checks of the displacement network: the residual module against the Eigen
// Tcn on random weights (with skip projections; also the release variant), the last-step
// forward training uses against the full forward (values and gradients), and tiny training
// runs on a synthetic flight.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "hdvio/core/lie.h"
#include "hdvio/learned/displacement_examples.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/displacement_trainer.h"
#include "hdvio/learned/torch/tcn_module.h"

namespace hdvio::learned {
namespace {

TEST(DisplacementTorch, ResidualModuleMatchesEigen) {
  torch::manual_seed(5);
  TcnModule module(TcnArchitecture::imo());
  torch::NoGradGuard no_grad;
  module->setNormalization(torch::tensor({0.1f, -0.2f, 9.5f, 0.0f, 0.1f, -0.1f}),
                           torch::tensor({1.5f, 1.2f, 2.0f, 0.8f, 0.9f, 0.5f}));
  const torch::Tensor x = torch::randn({1, 6, 70}) * 2.0;
  const torch::Tensor ref = module->forward(x)[0].contiguous();
  const Tcn tcn = exportTcn(module);
  EXPECT_EQ(tcn.weights().skip[0].weight.rows(), 64);  // projections exported
  EXPECT_EQ(tcn.weights().skip[1].weight.size(), 0);
  MatrixXf in(6, 70);
  for (int c = 0; c < 6; ++c)
    for (int t = 0; t < 70; ++t) in(c, t) = x[0][c][t].item<float>();
  const MatrixXf out = tcn.forwardSequence(in);
  double max_err = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int t = 0; t < 70; ++t) max_err = std::max(max_err, std::abs(out(c, t) - ref[c][t].item<double>()));
  EXPECT_LT(max_err, 1e-5);
  const TcnOutput last = tcn.predictWindow(in.rightCols(50));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(last.force(c), ref[c][69].item<double>(), 1e-5);
  TcnModule back = importTcn(tcn);
  EXPECT_LT((back->forward(x) - module->forward(x)).abs().max().item<double>(), 1e-6);
}

// Random weights and a normalization that is not the identity.
TcnModule randomModule(const TcnArchitecture& a, int seed) {
  torch::manual_seed(seed);
  TcnModule module(a);
  module->setNormalization(torch::tensor({0.1f, -0.2f, 9.5f, 0.0f, 0.1f, -0.1f}),
                           torch::tensor({1.5f, 1.2f, 2.0f, 0.8f, 0.9f, 0.5f}));
  return module;
}

TEST(DisplacementTorch, ReleaseVariantModuleMatchesEigen) {
  TcnModule module = randomModule(TcnArchitecture::imoRelease(), 9);
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({3, 6, 50}) * 2.0;
  const torch::Tensor ref = module->forward(x).select(2, 49);
  const Tcn tcn = exportTcn(module);
  ASSERT_TRUE(tcn.architecture().block_relu);
  for (int b = 0; b < 3; ++b) {
    MatrixXf in(6, 50);
    for (int c = 0; c < 6; ++c)
      for (int t = 0; t < 50; ++t) in(c, t) = x[b][c][t].item<float>();
    const TcnOutput out = tcn.predictWindow(in);  // zero padding of the 255-sample receptive field
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.force(c), ref[b][c].item<double>(), 1e-5);
  }
}

TEST(DisplacementTorch, LastStepForwardEqualsFullForwardWithGradients) {
  for (const TcnArchitecture& a : {TcnArchitecture::imo(), TcnArchitecture::imoRelease()}) {
    TcnModule module = randomModule(a, 11);
    const torch::Tensor x = torch::randn({4, 6, 50}) * 2.0;
    const torch::Tensor full = module->forward(x).select(2, 49);
    const torch::Tensor last = module->forwardLast(x);
    ASSERT_EQ(last.sizes(), full.sizes());
    EXPECT_LT((last - full).abs().max().item<double>(), 1e-5);
    // Same gradients: a loss on either path moves the weights alike.
    const torch::Tensor w = torch::randn({4, 3});
    module->zero_grad();
    (full * w).sum().backward();
    std::vector<torch::Tensor> g_full;
    for (const auto& p : module->parameters()) g_full.push_back(p.grad().clone());
    module->zero_grad();
    (module->forwardLast(x) * w).sum().backward();
    double worst = 0.0;
    std::size_t i = 0;
    for (const auto& p : module->parameters()) {
      const double scale = g_full[i].abs().max().item<double>() + 1e-6;
      worst = std::max(worst, (p.grad() - g_full[i]).abs().max().item<double>() / scale);
      ++i;
    }
    EXPECT_LT(worst, 1e-4) << (a.block_relu ? "release" : "imo");
  }
}

// 30 s of a smooth 3-D trajectory at 100 Hz, periodic with 5 pi s (so a validation flight at
// another phase shows states the training flight saw); thrust = specific force (no drag).
FlightSamples syntheticFlight(double phase) {
  FlightSamples f;
  f.name = "synthetic";
  f.rate_hz = 100.0;
  for (int k = 0; k < 3000; ++k) {
    const double t = k / 100.0 + phase;
    const Vec3 p(4 * std::sin(0.8 * t), 3 * std::cos(0.4 * t), 1 + 0.5 * std::sin(1.2 * t));
    const Vec3 v(3.2 * std::cos(0.8 * t), -1.2 * std::sin(0.4 * t), 0.6 * std::cos(1.2 * t));
    const Vec3 a(-2.56 * std::sin(0.8 * t), -0.48 * std::cos(0.4 * t), -0.72 * std::sin(1.2 * t));
    const Quat q = quatExp(Vec3(0.15 * std::sin(0.8 * t), 0.1 * std::cos(0.4 * t), 0.3 * std::sin(0.4 * t)));
    f.t.push_back(fromSeconds(t));
    f.p_W.push_back(p);
    f.v_W.push_back(v);
    f.q_WB.push_back(q);
    f.force.push_back(q.conjugate() * (a - gravityWorld()));
    f.thrust.push_back(f.force.back());
    f.gyro.push_back(Vec3(0.12 * std::cos(0.8 * t), -0.04 * std::sin(0.4 * t), 0.12 * std::cos(0.4 * t)));
  }
  return f;
}

// A 3-layer residual TCN on 20-sample windows (receptive field 15) and the options of a short
// run on the synthetic flights.
TcnArchitecture smallTcn() {
  TcnArchitecture a;
  a.residual = true;
  a.window = 20;
  a.layers = {{16, 4}, {16, 2}, {16, 1}};
  return a;
}

DisplacementTrainOptions shortRun(double learning_rate) {
  DisplacementTrainOptions o;
  o.stride_samples = 4;
  o.batch_size = 32;
  o.learning_rate = learning_rate;
  return o;
}

// Two trainings with the same options in one process (the second starting from whatever the
// first left in torch's generator) end with the same weights: the seed sets the initial weights
// too, so a training command repeats.
TEST(DisplacementTorch, SameOptionsTrainTheSameWeights) {
  DisplacementTrainOptions o = shortRun(3e-3);
  o.fixed_epochs = 2;
  const auto outputs = [&](int seed) {
    DisplacementTrainOptions r = o;
    r.seed = seed;
    DisplacementTrainer trainer(smallTcn(), r);
    std::ostringstream log;
    trainer.train({syntheticFlight(0.0)}, {}, log);
    torch::NoGradGuard no_grad;
    torch::manual_seed(3);
    return trainer.module()->forwardLast(torch::randn({4, 6, 20}));
  };
  const torch::Tensor first = outputs(7);
  EXPECT_TRUE(torch::equal(first, outputs(7)));
  EXPECT_GT((first - outputs(8)).abs().max().item<double>(), 1e-4);  // the seed matters
}

// A training stopped after any epoch and resumed from its checkpoint folder ends with the
// weights, best epoch and history of one that ran through (long trainings can be killed and
// continued).
TEST(DisplacementTorch, ResumedTrainingEqualsAnUninterruptedOne) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hdvio_resume_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  DisplacementTrainOptions o = shortRun(3e-3);
  o.max_epochs = 5;
  o.patience = 5;
  o.max_minutes = 1.0;
  const auto run = [&](const std::string& folder, int epochs, bool resume) {
    DisplacementTrainOptions r = o;
    r.max_epochs = epochs;
    r.checkpoint_dir = (dir / folder).string();
    r.resume = resume;
    std::filesystem::create_directories(r.checkpoint_dir);
    DisplacementTrainer trainer(smallTcn(), r);
    std::ostringstream log;
    return trainer.train({syntheticFlight(0.0)}, {syntheticFlight(7.0)}, log);
  };
  const auto through = run("through", 5, false);
  run("stopped", 2, false);
  const auto resumed = run("stopped", 5, true);
  EXPECT_EQ(resumed.best_epoch, through.best_epoch);
  ASSERT_EQ(resumed.history.size(), through.history.size());
  for (std::size_t e = 0; e < through.history.size(); ++e)
    EXPECT_EQ(resumed.history[e].validation_loss, through.history[e].validation_loss) << e;
  EXPECT_EQ(formatTcnWeights(resumed.best), formatTcnWeights(through.best));
  // Without a checkpoint there is nothing to resume.
  EXPECT_THROW(run("empty", 5, true), std::invalid_argument);
  std::filesystem::remove_all(dir);
}

TEST(DisplacementTorch, TinyRunReducesValidationError) {
  const TcnArchitecture a = smallTcn();
  DisplacementTrainOptions o = shortRun(3e-3);
  o.max_epochs = 8;
  o.patience = 8;
  o.max_minutes = 1.0;
  DisplacementTrainer trainer(a, o);
  std::ostringstream log;
  const auto result = trainer.train({syntheticFlight(0.0)}, {syntheticFlight(7.0)}, log);
  ASSERT_GE(result.history.size(), 2u);
  const double first = result.history.front().validation_loss;
  const double best = result.history[result.best_epoch].validation_loss;
  EXPECT_LT(best, 0.3 * first) << log.str();
  // The reported sigma is the Eigen model's RMSE on the validation windows.
  EXPECT_NEAR(result.validation_rmse.squaredNorm(), best, 0.05 * best + 1e-6);
}

TEST(DisplacementTorch, FixedEpochRunWithHuberLossKeepsTheLastEpoch) {
  TcnArchitecture a;
  a.residual = true;
  a.block_relu = true;
  a.window_padding = true;
  a.window = 20;
  a.layers = {{16, 1}, {16, 4}, {16, 16}};  // receptive field 43 > 20: padded, as the release
  DisplacementTrainOptions o;
  o.stride_samples = 4;
  o.batch_size = 32;
  o.learning_rate = 3e-3;
  o.loss = DisplacementLoss::kHuber;
  o.huber_delta = 0.5;
  o.orientation_perturbation = OrientationPerturbation::kUniformAngle;
  o.orientation_sigma_deg = 8.0;
  o.fixed_epochs = 4;
  o.patience = 1;  // ignored with a fixed epoch count
  DisplacementTrainer trainer(a, o);
  std::ostringstream log;
  const auto result = trainer.train({syntheticFlight(0.0)}, {}, log);  // no validation flights
  ASSERT_EQ(result.history.size(), 5u) << log.str();
  EXPECT_EQ(result.best_epoch, 4);
  EXPECT_LT(result.history.back().train_loss, 0.5 * result.history[1].train_loss) << log.str();
  // The kept weights are the last epoch's.
  TcnModule last = importTcn(result.best);
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({2, 6, 20});
  EXPECT_LT((last->forwardLast(x) - trainer.module()->forwardLast(x)).abs().max().item<double>(), 1e-6);
}

}  // namespace
}  // namespace hdvio::learned
