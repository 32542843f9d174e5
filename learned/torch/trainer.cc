#include "hdvio/learned/torch/trainer.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <stdexcept>

#include "hdvio/core/sequence.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/epoch_loop.h"

namespace hdvio::learned {
namespace {

// Trapezoidal preintegration weights over L intervals and L + 1 samples:
// beta = dt * sum_k wb_k a_k, alpha = dt^2 * sum_k wa_k a_k.
void trapezoidWeights(int L, std::vector<double>* wa, std::vector<double>* wb) {
  wa->assign(L + 1, 0.0);
  wb->assign(L + 1, 0.0);
  for (int m = 0; m < L; ++m) {  // interval m uses (a_m + a_{m+1}) / 2
    const double beta_w = 1.0, alpha_w = (L - 1 - m) + 0.5;
    (*wb)[m] += 0.5 * beta_w;
    (*wb)[m + 1] += 0.5 * beta_w;
    (*wa)[m] += 0.5 * alpha_w;
    (*wa)[m + 1] += 0.5 * alpha_w;
  }
}

torch::Tensor toTensor(const std::vector<double>& v) {
  return torch::tensor(std::vector<float>(v.begin(), v.end()));
}

}  // namespace

SegmentSet buildSegments(const std::vector<FlightSamples>& flights, int window,
                         const TrainOptions& options) {
  SegmentSet set;
  if (flights.empty()) throw std::invalid_argument("no flights to build training segments from");
  const double rate = flights.front().rate_hz;
  set.dt = 1.0 / rate;
  set.length = std::max(1, static_cast<int>(std::lround(options.segment_seconds * rate)));
  const int L = set.length;
  const double dt = set.dt, span = L * dt;
  std::vector<double> wa, wb;
  trapezoidWeights(L, &wa, &wb);
  std::vector<float> x, rot, ar, br;
  int64_t n = 0;
  for (const auto& f : flights) {
    if (std::abs(f.rate_hz - rate) > 1e-9) throw std::invalid_argument("flights have different rates");
    for (std::size_t i = window - 1; i + L < f.size(); i += options.stride_samples) {
      const std::size_t j = i + L;
      const Mat3 Ri_T = f.q_WB[i].toRotationMatrix().transpose();
      for (int c = 0; c < 6; ++c) {
        for (std::size_t k = i + 1 - window; k <= j; ++k) {
          x.push_back(static_cast<float>(c < 3 ? f.thrust[k](c) : f.gyro[k](c - 3)));
        }
      }
      Vec3 alpha_thrust = Vec3::Zero(), beta_thrust = Vec3::Zero();
      for (std::size_t k = i; k <= j; ++k) {
        const Mat3 dR = Ri_T * f.q_WB[k].toRotationMatrix();
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) rot.push_back(static_cast<float>(dR(r, c)));
        // Thrust plus the drag law at the true body velocity: the network learns the rest.
        const Vec3 a = dR * (f.thrust[k] + options.drag.force(f.q_WB[k].conjugate() * f.v_W[k], f.thrust[k].norm()));
        alpha_thrust += dt * dt * wa[k - i] * a;
        beta_thrust += dt * wb[k - i] * a;
      }
      const Vec3 g = gravityWorld();
      const Vec3 alpha_gt = Ri_T * (f.p_W[j] - f.p_W[i] - f.v_W[i] * span - 0.5 * g * span * span);
      const Vec3 beta_gt = Ri_T * (f.v_W[j] - f.v_W[i] - g * span);
      for (int c = 0; c < 3; ++c) {
        ar.push_back(static_cast<float>(alpha_gt(c) - alpha_thrust(c)));
        br.push_back(static_cast<float>(beta_gt(c) - beta_thrust(c)));
      }
      ++n;
    }
  }
  if (n == 0) throw std::invalid_argument("flights are too short for one training segment");
  set.inputs = torch::tensor(x).reshape({n, 6, L + window});
  set.rotations = torch::tensor(rot).reshape({n, L + 1, 3, 3});
  set.alpha_rest = torch::tensor(ar).reshape({n, 3});
  set.beta_rest = torch::tensor(br).reshape({n, 3});
  return set;
}

Trainer::Trainer(TcnArchitecture architecture, TrainOptions options)
    : arch_(std::move(architecture)), options_(std::move(options)), module_(nullptr) {
  torch::manual_seed(options_.seed);
  module_ = TcnModule(arch_);
}

std::vector<double> Trainer::pass(const SegmentSet& set, torch::optim::Adam* optimizer) {
  const bool training = optimizer != nullptr;
  module_->train(training);
  std::optional<torch::NoGradGuard> no_grad;
  if (!training) no_grad.emplace();
  const int L = set.length, W = arch_.window;
  const double dt = set.dt, span = L * dt;
  std::vector<double> wa, wb;
  trapezoidWeights(L, &wa, &wb);
  const torch::Tensor wa_t = toTensor(wa).view({1, -1, 1}), wb_t = toTensor(wb).view({1, -1, 1});
  const int64_t n = set.size();
  const torch::Tensor order = training ? torch::randperm(n) : torch::arange(n);
  double loss_sum = 0.0, ea_sum = 0.0, eb_sum = 0.0;
  for (int64_t start = 0; start < n; start += options_.batch_size) {
    const torch::Tensor idx = order.slice(0, start, std::min<int64_t>(n, start + options_.batch_size));
    torch::Tensor x = set.inputs.index_select(0, idx);
    if (training && options_.gyro_bias_sigma > 0.0) {
      // Gyro-bias augmentation: one constant offset per segment on the gyro channels.
      const torch::Tensor offset = options_.gyro_bias_sigma * torch::randn({x.size(0), 3, 1});
      x = torch::cat({x.slice(1, 0, 3), x.slice(1, 3, 6) + offset}, 1);
    }
    const torch::Tensor out = module_->forward(x).slice(2, W - 1, W + L);  // B x C x (L + 1)
    const torch::Tensor force = out.slice(1, 0, 3).transpose(1, 2);       // B x (L+1) x 3
    const torch::Tensor R = set.rotations.index_select(0, idx);
    const torch::Tensor rotated = torch::matmul(R, force.unsqueeze(-1)).squeeze(-1);
    const torch::Tensor alpha = dt * dt * (wa_t * rotated).sum(1);
    const torch::Tensor beta = dt * (wb_t * rotated).sum(1);
    const torch::Tensor ea = (alpha - set.alpha_rest.index_select(0, idx)) / (0.5 * span * span);
    const torch::Tensor eb = (beta - set.beta_rest.index_select(0, idx)) / span;
    torch::Tensor loss = (ea.square().sum(1) + eb.square().sum(1)).mean();
    if (arch_.variance_head) {
      // Gaussian NLL of the velocity error under the predicted per-sample variances,
      // propagated through the preintegration; the mean is not pulled by this term.
      const torch::Tensor var = out.slice(1, 3, 6).transpose(1, 2).clamp(-20.0, 10.0).exp();
      const torch::Tensor cov_k = torch::matmul(R * var.unsqueeze(-2), R.transpose(-1, -2));
      const torch::Tensor cov = (wb_t.unsqueeze(-1).square() * cov_k).sum(1) * (dt * dt / (span * span)) +
                                1e-8 * torch::eye(3).unsqueeze(0);
      const torch::Tensor e = eb.detach().unsqueeze(-1);
      const torch::Tensor nll =
          0.5 * (torch::matmul(e.transpose(1, 2), torch::linalg::solve(cov, e, true)).squeeze() +
                 torch::logdet(cov));
      loss = loss + options_.variance_weight * nll.mean();
    }
    if (training) {
      optimizer->zero_grad();
      loss.backward();
      optimizer->step();
    }
    const double b = static_cast<double>(idx.size(0));
    loss_sum += loss.item<double>() * b;
    ea_sum += ea.square().sum().item<double>();
    eb_sum += eb.square().sum().item<double>();
  }
  return {loss_sum / n, std::sqrt(ea_sum / (3.0 * n)), std::sqrt(eb_sum / (3.0 * n))};
}

TrainingResult Trainer::train(const std::vector<FlightSamples>& train_flights,
                              const std::vector<FlightSamples>& validation_flights,
                              std::ostream& log) {
  torch::set_num_threads(options_.threads);
  torch::manual_seed(options_.seed);
  if (std::abs(train_flights.front().rate_hz - arch_.sample_rate_hz) > 1e-6) {
    throw std::invalid_argument("flights are sampled at a different rate than the model");
  }
  const SegmentSet train_set = buildSegments(train_flights, arch_.window, options_);
  const SegmentSet val_set = buildSegments(validation_flights, arch_.window, options_);
  // Normalization from the training inputs (per channel over all samples).
  const torch::Tensor flat = train_set.inputs.transpose(0, 1).reshape({6, -1});
  module_->setNormalization(flat.mean(1), flat.std(1).clamp_min(1e-3));
  log << "training segments " << train_set.size() << ", validation segments " << val_set.size()
      << ", segment " << train_set.length << " samples, parameters " << exportTcn(module_).parameterCount()
      << "\n";

  torch::optim::Adam optimizer(module_->parameters(), torch::optim::AdamOptions(options_.learning_rate));
  TrainingResult result{{}, 0, exportTcn(module_)};
  const auto run_epoch = [&](int epoch, std::ostream& out) {
    const auto t0 = std::chrono::steady_clock::now();
    EpochStats s;
    s.epoch = epoch;
    s.train_loss = pass(train_set, epoch > 0 ? &optimizer : nullptr)[0];
    const std::vector<double> v = pass(val_set, nullptr);
    s.validation_loss = v[0];
    s.validation_alpha_rms = v[1];
    s.validation_beta_rms = v[2];
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.history.push_back(s);
    out << "epoch " << std::setw(3) << epoch << "  train " << std::setprecision(5) << s.train_loss
        << "  val " << s.validation_loss << "  val_rms(alpha, beta) " << s.validation_alpha_rms
        << ", " << s.validation_beta_rms << " m/s^2  " << std::setprecision(3) << s.seconds << " s";
    return s.validation_loss;
  };
  const EpochLoopResult loop = runEpochLoop(
      {options_.max_epochs, options_.patience, options_.max_minutes, options_.checkpoint_dir, true},
      module_, run_epoch, log);
  result.best_epoch = loop.best_epoch;
  result.best = loop.best;
  return result;
}

}  // namespace hdvio::learned
