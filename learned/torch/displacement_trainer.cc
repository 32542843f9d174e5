#include "hdvio/learned/torch/displacement_trainer.h"

#include <ATen/CPUGeneratorImpl.h>

#include <chrono>
#include <filesystem>
#include <mutex>
#include <ctime>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <stdexcept>

#include "hdvio/learned/displacement_examples.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/epoch_loop.h"

namespace hdvio::learned {
namespace {

// Exp of a batch of rotation vectors (B x 3) -> B x 3 x 3 (Rodrigues).
torch::Tensor expBatch(const torch::Tensor& w) {
  const torch::Tensor theta = w.norm(2, 1, true).clamp_min(1e-12);  // B x 1
  const torch::Tensor a = w / theta;
  const torch::Tensor zero = torch::zeros_like(a.select(1, 0));
  const torch::Tensor K = torch::stack({zero, -a.select(1, 2), a.select(1, 1),
                                        a.select(1, 2), zero, -a.select(1, 0),
                                        -a.select(1, 1), a.select(1, 0), zero}, 1)
                              .view({-1, 3, 3});
  const torch::Tensor s = theta.sin().view({-1, 1, 1}), c = theta.cos().view({-1, 1, 1});
  return torch::eye(3).unsqueeze(0) + s * K + (1.0 - c) * torch::matmul(K, K);
}

}  // namespace

DisplacementSet buildDisplacementSet(const std::vector<FlightSamples>& flights, int window,
                                     DisplacementInputKind kind, int stride) {
  const std::vector<DisplacementExample> ex = displacementExamples(flights, window, stride);
  const auto n = static_cast<int64_t>(ex.size());
  DisplacementSet set;
  set.inputs = torch::empty({n, 6, window}, torch::kFloat32);
  set.rotations = torch::empty({n, window, 3, 3}, torch::kFloat32);
  set.targets = torch::empty({n, 3}, torch::kFloat32);
  auto in = set.inputs.accessor<float, 3>();
  auto rot = set.rotations.accessor<float, 4>();
  auto tg = set.targets.accessor<float, 2>();
  for (int64_t i = 0; i < n; ++i) {
    const FlightSamples& f = flights[ex[i].flight];
    const MatrixXf x = worldWindow(f, ex[i].end, window, kind);
    const Vec3 d = displacementTarget(f, ex[i].end, window);
    for (int k = 0; k < window; ++k) {
      for (int c = 0; c < 6; ++c) in[i][c][k] = x(c, k);
      const Mat3 R = f.q_WB[ex[i].end + 1 - window + k].toRotationMatrix();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) rot[i][k][r][c] = static_cast<float>(R(r, c));
    }
    for (int c = 0; c < 3; ++c) tg[i][c] = static_cast<float>(d(c));
  }
  return set;
}

DisplacementTrainer::DisplacementTrainer(TcnArchitecture architecture, DisplacementTrainOptions options)
    : arch_(std::move(architecture)), options_(std::move(options)), module_(nullptr) {
  // The initial weights come from the seed, not from whatever the process drew before.
  torch::manual_seed(static_cast<uint64_t>(options_.seed));
  module_ = TcnModule(arch_);
  if (arch_.input_channels != 6) throw std::invalid_argument("the displacement network takes 6 inputs");
}

std::pair<torch::Tensor, torch::Tensor> DisplacementTrainer::augment(const DisplacementSet& set,
                                                                     const torch::Tensor& idx) const {
  const torch::Tensor x = set.inputs.index_select(0, idx);  // B x 6 x W
  const int64_t b = x.size(0);
  const torch::Tensor R = set.rotations.index_select(0, idx);  // B x W x 3 x 3
  // A constant bias error e in the body frame adds R_k e to the world-frame sample k.
  auto biased = [&](const torch::Tensor& part, double range) {
    if (range <= 0.0) return part;
    const torch::Tensor e = (2.0 * torch::rand({b, 1, 3, 1}) - 1.0) * range;
    return part + torch::matmul(R, e).squeeze(-1).transpose(1, 2);  // B x 3 x W
  };
  torch::Tensor force = x.slice(1, 0, 3), gyro = biased(x.slice(1, 3, 6), options_.gyro_bias_range);
  if (options_.kind == DisplacementInputKind::kAccelGyro) force = biased(force, options_.accel_bias_range);
  if (options_.orientation_sigma_deg > 0.0) {
    const double sigma = options_.orientation_sigma_deg * M_PI / 180.0;
    torch::Tensor delta;
    if (options_.orientation_perturbation == OrientationPerturbation::kGaussian) {
      delta = torch::randn({b, 3}) * sigma;
    } else {
      const torch::Tensor axis = torch::randn({b, 3});
      delta = axis / axis.norm(2, 1, true).clamp_min(1e-12) * (torch::rand({b, 1}) * sigma);
    }
    const torch::Tensor dR = expBatch(delta);
    force = torch::matmul(dR, force);
    gyro = torch::matmul(dR, gyro);
  }
  const torch::Tensor target = set.targets.index_select(0, idx);  // B x 3
  return {torch::cat({force, gyro}, 1), target};
}

torch::Tensor DisplacementTrainer::loss(const torch::Tensor& prediction, const torch::Tensor& target) const {
  if (options_.loss == DisplacementLoss::kHuber) {
    return torch::nn::functional::huber_loss(
        prediction, target, torch::nn::functional::HuberLossFuncOptions().delta(options_.huber_delta));
  }
  return (prediction - target).square().sum(1).mean();
}

Eigen::Vector3d DisplacementTrainer::pass(const DisplacementSet& set, torch::optim::Adam* optimizer) {
  const bool training = optimizer != nullptr;
  module_->train(training);
  std::optional<torch::NoGradGuard> no_grad;
  if (!training) no_grad.emplace();
  const int64_t n = set.size();
  const torch::Tensor order = training ? torch::randperm(n) : torch::arange(n);
  torch::Tensor sum = torch::zeros({3}, torch::kFloat64);
  for (int64_t start = 0; start < n; start += options_.batch_size) {
    const torch::Tensor idx = order.slice(0, start, std::min<int64_t>(n, start + options_.batch_size));
    const auto [x, target] = training ? augment(set, idx)
                                      : std::pair(set.inputs.index_select(0, idx), set.targets.index_select(0, idx));
    const torch::Tensor out = module_->forwardLast(x).slice(1, 0, 3);  // B x 3
    if (training) {
      const torch::Tensor l = loss(out, target);
      optimizer->zero_grad();
      l.backward();
      optimizer->step();
    }
    sum += (out.detach() - target).square().sum(0).to(torch::kFloat64);
  }
  Eigen::Vector3d mse = Eigen::Vector3d::Zero();
  for (int c = 0; c < 3; ++c) mse(c) = n > 0 ? sum[c].item<double>() / static_cast<double>(n) : 0.0;
  return mse;
}

double DisplacementTrainer::trainingWindowsPerSecond(const std::vector<FlightSamples>& flights, int batches,
                                                     int threads, double* cpu_seconds) {
  torch::set_num_threads(threads);
  const DisplacementSet set = buildDisplacementSet(flights, arch_.window, options_.kind, options_.stride_samples);
  if (set.size() < options_.batch_size) throw std::invalid_argument("fewer windows than one batch");
  torch::optim::Adam optimizer(module_->parameters(), torch::optim::AdamOptions(options_.learning_rate));
  module_->train(true);
  const torch::Tensor order = torch::randperm(set.size());
  const auto step = [&](int i) {
    const int64_t start = (static_cast<int64_t>(i) * options_.batch_size) % (set.size() - options_.batch_size + 1);
    const torch::Tensor idx = order.slice(0, start, start + options_.batch_size);
    const auto [x, target] = augment(set, idx);
    const torch::Tensor l = loss(module_->forwardLast(x).slice(1, 0, 3), target);
    optimizer.zero_grad();
    l.backward();
    optimizer.step();
  };
  step(0);  // warm-up (allocations)
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  for (int i = 1; i <= batches; ++i) step(i);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (cpu_seconds) *cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return static_cast<double>(batches) * options_.batch_size / s;
}

struct DisplacementTrainer::Resumed {
  int epoch = 0;  // the last finished epoch
  int best_epoch = 0;
  double best_loss = 0.0;
};

void DisplacementTrainer::saveResumeState(int epoch, int best_epoch, double best_loss,
                                          torch::optim::Adam& optimizer,
                                          const std::vector<DisplacementEpoch>& history) {
  torch::serialize::OutputArchive archive, module, adam;
  module_->save(module);
  optimizer.save(adam);
  archive.write("module", module);
  archive.write("optimizer", adam);
  auto generator = at::detail::getDefaultCPUGenerator();
  {
    std::lock_guard<std::mutex> lock(generator.mutex());
    archive.write("rng_state", generator.get_state());
  }
  archive.write("epoch", torch::tensor(static_cast<int64_t>(epoch)));
  archive.write("best_epoch", torch::tensor(static_cast<int64_t>(best_epoch)));
  archive.write("best_loss", torch::tensor(best_loss, torch::kFloat64));
  torch::Tensor h = torch::zeros({static_cast<int64_t>(history.size()), 7}, torch::kFloat64);
  for (std::size_t i = 0; i < history.size(); ++i) {
    const DisplacementEpoch& e = history[i];
    const double row[7] = {static_cast<double>(e.epoch), e.train_loss, e.validation_loss,
                           e.validation_axis_mse.x(), e.validation_axis_mse.y(), e.validation_axis_mse.z(), e.seconds};
    for (int c = 0; c < 7; ++c) h[static_cast<int64_t>(i)][c] = row[c];
  }
  archive.write("history", h);
  const std::string path = options_.checkpoint_dir + "/resume.pt";
  archive.save_to(path + ".tmp");
  std::filesystem::rename(path + ".tmp", path);
}

DisplacementTrainer::Resumed DisplacementTrainer::loadResumeState(torch::optim::Adam& optimizer,
                                                                  std::vector<DisplacementEpoch>* history) {
  const std::string path = options_.checkpoint_dir + "/resume.pt";
  if (!std::filesystem::exists(path)) throw std::invalid_argument(path + ": no checkpoint to resume from");
  torch::serialize::InputArchive archive, module, adam;
  archive.load_from(path);
  archive.read("module", module);
  archive.read("optimizer", adam);
  module_->load(module);
  optimizer.load(adam);
  torch::Tensor rng, epoch, best_epoch, best_loss, h;
  archive.read("rng_state", rng);
  archive.read("epoch", epoch);
  archive.read("best_epoch", best_epoch);
  archive.read("best_loss", best_loss);
  archive.read("history", h);
  auto generator = at::detail::getDefaultCPUGenerator();
  {
    std::lock_guard<std::mutex> lock(generator.mutex());
    generator.set_state(rng);
  }
  history->clear();
  for (int64_t i = 0; i < h.size(0); ++i) {
    DisplacementEpoch e;
    e.epoch = static_cast<int>(h[i][0].item<double>());
    e.train_loss = h[i][1].item<double>();
    e.validation_loss = h[i][2].item<double>();
    e.validation_axis_mse = Eigen::Vector3d(h[i][3].item<double>(), h[i][4].item<double>(), h[i][5].item<double>());
    e.seconds = h[i][6].item<double>();
    history->push_back(e);
  }
  return {static_cast<int>(epoch.item<int64_t>()), static_cast<int>(best_epoch.item<int64_t>()),
          best_loss.item<double>()};
}

DisplacementTrainingResult DisplacementTrainer::train(const std::vector<FlightSamples>& train_flights,
                                                      const std::vector<FlightSamples>& validation_flights,
                                                      std::ostream& log) {
  torch::set_num_threads(options_.threads);
  torch::manual_seed(static_cast<uint64_t>(options_.seed));
  for (const auto& f : train_flights) {
    if (std::abs(f.rate_hz - arch_.sample_rate_hz) > 1e-6) {
      throw std::invalid_argument(f.name + " is sampled at a different rate than the model");
    }
  }
  const DisplacementSet train_set =
      buildDisplacementSet(train_flights, arch_.window, options_.kind, options_.stride_samples);
  const DisplacementSet val_set =
      buildDisplacementSet(validation_flights, arch_.window, options_.kind, options_.stride_samples);
  const bool fixed = options_.fixed_epochs > 0;
  if (train_set.size() == 0 || (val_set.size() == 0 && !fixed)) {
    throw std::invalid_argument("no complete training or validation window");
  }
  const torch::Tensor flat = train_set.inputs.transpose(0, 1).reshape({6, -1});
  module_->setNormalization(flat.mean(1), flat.std(1).clamp_min(1e-3));
  log << "training windows " << train_set.size() << ", validation windows " << val_set.size()
      << ", window " << arch_.window << " samples, receptive field " << arch_.receptiveField()
      << ", parameters " << exportTcn(module_).parameterCount() << "\n";

  torch::optim::Adam optimizer(module_->parameters(), torch::optim::AdamOptions(options_.learning_rate));
  DisplacementTrainingResult result{{}, 0, exportTcn(module_), {}};
  std::optional<EpochLoopStart> start;
  if (options_.resume) {
    if (options_.checkpoint_dir.empty()) throw std::invalid_argument("resuming needs a checkpoint folder");
    const Resumed r = loadResumeState(optimizer, &result.history);
    start = EpochLoopStart{r.epoch + 1, r.best_loss,
                           {r.best_epoch, loadTcnWeights(options_.checkpoint_dir + "/best.tcn")}};
    log << "resumed after epoch " << r.epoch << " (best so far: epoch " << r.best_epoch << ")\n";
  }
  const EpochEnd save_state = [&](int epoch, const EpochLoopResult& best, double best_loss) {
    if (!options_.checkpoint_dir.empty()) saveResumeState(epoch, best.best_epoch, best_loss, optimizer, result.history);
  };
  const auto run_epoch = [&](int epoch, std::ostream& out) {
    const auto t0 = std::chrono::steady_clock::now();
    DisplacementEpoch s;
    s.epoch = epoch;
    s.train_loss = pass(train_set, epoch > 0 ? &optimizer : nullptr).sum();
    s.validation_axis_mse = val_set.size() > 0 ? pass(val_set, nullptr) : Eigen::Vector3d::Constant(NAN);
    s.validation_loss = s.validation_axis_mse.sum();
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.history.push_back(s);
    if (options_.save_every > 0 && !options_.checkpoint_dir.empty() && epoch % options_.save_every == 0 &&
        val_set.size() > 0) {
      TcnFileInfo info;
      info.task = "displacement";
      info.inputs = toString(options_.kind);
      info.output_sigma = {std::sqrt(s.validation_axis_mse.x()), std::sqrt(s.validation_axis_mse.y()),
                           std::sqrt(s.validation_axis_mse.z())};
      saveTcnFile(exportTcn(module_), info, options_.checkpoint_dir + "/epoch_" + std::to_string(epoch) + ".tcn",
                  "epoch " + std::to_string(epoch) + " (output_sigma: this epoch's validation RMSE)",
                  TcnEncoding::kFloat32);
    }
    out << "epoch " << std::setw(3) << epoch << "  train " << std::setprecision(5) << s.train_loss
        << "  val " << s.validation_loss << " m^2  lr " << options_.learning_rate << "  "
        << std::setprecision(3) << s.seconds << " s (process CPU "
        << static_cast<double>(std::clock()) / CLOCKS_PER_SEC / 60.0 << " min)";
    return s.validation_loss;
  };
  const EpochLoopResult loop = runEpochLoop(
      {fixed ? options_.fixed_epochs : options_.max_epochs, options_.patience, options_.max_minutes,
       options_.checkpoint_dir, false, fixed},
      module_, run_epoch, log, save_state, start ? &*start : nullptr);
  result.best_epoch = loop.best_epoch;
  result.best = loop.best;
  // Per-axis validation RMSE of the best weights (Eigen inference, as deployed).
  const std::vector<DisplacementExample> ex =
      displacementExamples(validation_flights, arch_.window, options_.stride_samples);
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  for (const auto& e : ex) {
    const FlightSamples& f = validation_flights[e.flight];
    const Vec3 d = result.best.predictWindow(worldWindow(f, e.end, arch_.window, options_.kind)).force.cast<double>();
    sq += (d - displacementTarget(f, e.end, arch_.window)).cwiseAbs2();
  }
  result.validation_rmse = ex.empty() ? Eigen::Vector3d::Constant(NAN)
                                      : Eigen::Vector3d((sq / static_cast<double>(ex.size())).cwiseSqrt());
  return result;
}

}  // namespace hdvio::learned
