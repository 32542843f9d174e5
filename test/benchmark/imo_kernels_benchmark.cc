// Per-call cost of the IMO filter's parts (they set its real-time factor on one core): one IMU
// propagation step, one grid step at steady state (clone, displacement update between the
// clones one window apart, marginalization of the oldest clone), and the displacement
// networks' forward pass over one window with random weights: the IMO release's architecture
// (imo_blackbird.tcn), imo_dido.yaml's twelve 32-channel versions of it in turn (imo_dido_*.tcn,
// about 1.3 MB of weights: what an update costs in the filter). The TLIO-style networks have the
// same shapes (tlio_blackbird.tcn, tlio_dido_*.tcn), so these rows give their cost too.
// Run: hdvio_imo_benchmarks --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/learned/tcn.h"

namespace hdvio {
namespace {

using imo::ImoFilter;

constexpr double kImuRate = 400.0;     // DIDO's IMU
constexpr int kStepsPerGrid = 20;      // 20 Hz updates
constexpr int kWindowClones = 10;      // 0.5 s window

imo::ImoNominalState startState() {
  imo::ImoNominalState x;
  x.v = Vec3(1.0, 0.5, 0.0);
  return x;
}

void propagateOnce(ImoFilter* f, std::mt19937* rng, Timestamp* t) {
  std::normal_distribution<double> n(0.0, 0.5);
  *t += fromSeconds(1.0 / kImuRate);
  f->propagate(Vec3(n(*rng), n(*rng), n(*rng)), Vec3(n(*rng), n(*rng), 9.81 + n(*rng)), *t);
}

// A filter holding a full window of clones, as between two updates of a run.
ImoFilter steadyFilter(std::mt19937* rng, Timestamp* t) {
  ImoFilter f{imo::ImoFilterOptions()};
  f.initialize(startState());
  f.addClone();
  for (int k = 0; k < kWindowClones; ++k) {
    for (int s = 0; s < kStepsPerGrid; ++s) propagateOnce(&f, rng, t);
    f.addClone();
  }
  return f;
}

void BM_ImoPropagateStep(benchmark::State& state) {
  std::mt19937 rng(1);
  Timestamp t = 0;
  ImoFilter f = steadyFilter(&rng, &t);
  for (auto _ : state) propagateOnce(&f, &rng, &t);
  benchmark::DoNotOptimize(f.state());
}
BENCHMARK(BM_ImoPropagateStep);

// Clone, update, marginalize: the "update" stage of a run, per grid step.
void BM_ImoGridStep(benchmark::State& state) {
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0.0, 0.01);
  Timestamp t = 0;
  ImoFilter f = steadyFilter(&rng, &t);
  for (auto _ : state) {
    state.PauseTiming();
    for (int s = 0; s < kStepsPerGrid; ++s) propagateOnce(&f, &rng, &t);
    state.ResumeTiming();
    f.addClone();
    const int j = static_cast<int>(f.clones().size()) - 1;
    imo::RelativePositionMeasurement m;
    m.clone_i = j - kWindowClones;
    m.clone_j = j;
    m.z = f.clones()[j].p - f.clones()[m.clone_i].p + Vec3(n(rng), n(rng), n(rng));
    m.covariance = 1e-4 * Mat3::Identity();
    benchmark::DoNotOptimize(f.update(m));
    f.marginalizeClone(0);
  }
}
BENCHMARK(BM_ImoGridStep);

learned::MatrixXf randomMatrix(std::mt19937* rng, long rows, long cols, float scale) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  learned::MatrixXf m(rows, cols);
  for (long i = 0; i < m.size(); ++i) m.data()[i] = scale * n(*rng);
  return m;
}

// A displacement network of architecture a (7 residual blocks, 248,771 parameters for both
// shipped ones) with random weights.
learned::Tcn displacementNetwork(const learned::TcnArchitecture& a, std::mt19937* rng) {
  learned::TcnWeights w;
  w.input_mean = learned::VectorXf::Zero(a.input_channels);
  w.input_std = learned::VectorXf::Ones(a.input_channels);
  int width = a.input_channels;
  for (const auto& l : a.layers) {
    for (int in : {width, l.out_channels}) {
      const float scale = 1.0f / std::sqrt(static_cast<float>(a.kernel_size * in));
      w.conv.push_back({randomMatrix(rng, l.out_channels, a.kernel_size * in, scale),
                        randomMatrix(rng, l.out_channels, 1, 0.1f)});
    }
    if (width == l.out_channels) {
      w.skip.emplace_back();
    } else {
      w.skip.push_back({randomMatrix(rng, l.out_channels, width, 1.0f / std::sqrt(float(width))),
                        randomMatrix(rng, l.out_channels, 1, 0.1f)});
    }
    width = l.out_channels;
  }
  w.head_weight = randomMatrix(rng, a.output_channels, width, 0.1f);
  w.head_bias = randomMatrix(rng, a.output_channels, 1, 0.1f);
  return learned::Tcn(a, w);
}

// One network of architecture a, window after window.
void networkWindow(benchmark::State& state, const learned::TcnArchitecture& a, unsigned seed) {
  std::mt19937 rng(seed);
  const learned::Tcn tcn = displacementNetwork(a, &rng);
  const learned::MatrixXf window = randomMatrix(&rng, 6, tcn.architecture().window, 1.0f);
  learned::TcnWorkspace workspace;
  for (auto _ : state) benchmark::DoNotOptimize(tcn.predictWindow(window, &workspace));
}

void BM_ImoNetworkWindow(benchmark::State& state) {
  networkWindow(state, learned::TcnArchitecture::imoRelease(), 3);
}
BENCHMARK(BM_ImoNetworkWindow);

// imo_dido.yaml's ensemble: twelve networks of the release's architecture with every block 32
// channels wide, each called once per iteration (one update).
void BM_ImoDidoEnsembleWindow(benchmark::State& state) {
  std::mt19937 rng(4);
  learned::TcnArchitecture narrow = learned::TcnArchitecture::imoRelease();
  for (learned::TcnLayerSpec& l : narrow.layers) l.out_channels = 32;
  std::vector<learned::Tcn> members;
  for (int k = 0; k < 12; ++k) members.push_back(displacementNetwork(narrow, &rng));
  const learned::MatrixXf window = randomMatrix(&rng, 6, members.front().architecture().window, 1.0f);
  learned::TcnWorkspace workspace;
  for (auto _ : state)
    for (const learned::Tcn& m : members) benchmark::DoNotOptimize(m.predictWindow(window, &workspace));
}
BENCHMARK(BM_ImoDidoEnsembleWindow);

}  // namespace
}  // namespace hdvio

BENCHMARK_MAIN();
