// Per-call cost of the estimator's inner kernels: preintegration per IMU sample and factor
// evaluation with Jacobians through the Ceres cost function (what the solver calls).
// Run: hdvio_kernel_benchmarks --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <type_traits>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/reprojection_factor.h"

namespace hdvio {
namespace {

using namespace symbols;

ImuStep randomImuStep(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  ImuStep s;
  s.dt = 0.0025;
  s.gyro = Vec3(n(rng), n(rng), n(rng));
  s.accel = Vec3(n(rng), n(rng), 9.81 + n(rng));
  return s;
}

DynamicsStep randomDynamicsStep(std::mt19937& rng) {
  const ImuStep i = randomImuStep(rng);
  DynamicsStep s;
  s.dt = i.dt;
  s.gyro = i.gyro;
  s.accel = i.accel;
  s.thrust = Vec3(0.0, 0.0, i.accel.z());
  return s;
}

void BM_ImuPreintegrationPerSample(benchmark::State& state) {
  std::mt19937 rng(1);
  std::vector<ImuStep> steps(400);
  for (auto& s : steps) s = randomImuStep(rng);
  for (auto _ : state) {
    ImuPreintegrator p(Vec6::Zero(), ImuNoiseParams(), /*keep_steps=*/false);
    for (const auto& s : steps) p.add(s);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(steps.size()));
}
BENCHMARK(BM_ImuPreintegrationPerSample);

void BM_ThrustPreintegrationPerSample(benchmark::State& state) {
  std::mt19937 rng(2);
  std::vector<DynamicsStep> steps(400);
  for (auto& s : steps) s = randomDynamicsStep(rng);
  for (auto _ : state) {
    ThrustPreintegrator p(Vec6::Zero(), ThrustNoiseParams(), /*keep_steps=*/false);
    for (const auto& s : steps) p.add(s);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(steps.size()));
}
BENCHMARK(BM_ThrustPreintegrationPerSample);

// Evaluates one factor's cost function with all Jacobians at a fixed random state.
void runEvaluate(benchmark::State& state, const Factor& f, const Values& values) {
  std::vector<const double*> params;
  std::vector<std::vector<double>> jac_storage;
  std::vector<double*> jacs;
  for (Key k : f.keys()) {
    params.push_back(values.data(k));
    jac_storage.emplace_back(f.dim() * values.ambientDim(k));
  }
  for (auto& j : jac_storage) jacs.push_back(j.data());
  std::vector<double> r(f.dim());
  ceres::CostFunction* cost = f.costFunction();
  for (auto _ : state) {
    benchmark::DoNotOptimize(cost->Evaluate(params.data(), r.data(), jacs.data()));
    benchmark::ClobberMemory();
  }
}

Values randomStates(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Values v;
  for (int k = 0; k < 2; ++k) {
    v.insertPose(X(k), Pose(quatExp(Vec3(n(rng), n(rng), n(rng))), Vec3(n(rng), n(rng), n(rng))));
    v.insertVector(V(k), Vec3(n(rng), n(rng), n(rng)));
    v.insertVector(F(k), Vec3(n(rng), n(rng), n(rng)));
    v.insertVector(B(k), 0.01 * Eigen::VectorXd::Random(6));
  }
  return v;
}

void BM_ImuFactorEvaluate(benchmark::State& state) {
  std::mt19937 rng(3);
  std::vector<ImuStep> steps(40);
  for (auto& s : steps) s = randomImuStep(rng);
  auto pim = std::make_shared<PreintegratedImu>(
      PreintegratedImu::integrate(steps, Vec6::Zero(), ImuNoiseParams()));
  ImuFactor f(X(0), V(0), B(0), X(1), V(1), B(1), pim);
  const Values v = randomStates(rng);
  runEvaluate(state, f, v);
}
BENCHMARK(BM_ImuFactorEvaluate);

// The factor's own residual and tangent Jacobians, without what FactorT (core) adds (fixed-size
// whitening with the factor's noise model and lifting to ambient size); the difference to
// BM_ImuFactorEvaluate is that.
void BM_ImuFactorWithoutFactorT(benchmark::State& state) {
  std::mt19937 rng(3);
  std::vector<ImuStep> steps(40);
  for (auto& s : steps) s = randomImuStep(rng);
  auto pim = std::make_shared<PreintegratedImu>(
      PreintegratedImu::integrate(steps, Vec6::Zero(), ImuNoiseParams()));
  ImuFactor f(X(0), V(0), B(0), X(1), V(1), B(1), pim);
  const Values v = randomStates(rng);
  std::vector<const double*> params;
  for (Key k : f.keys()) params.push_back(v.data(k));
  std::vector<double> r(15), jac_storage(15 * 30);
  double* jacs[6];
  const int tangent[6] = {6, 3, 6, 6, 3, 6};
  for (int i = 0, off = 0; i < 6; off += 15 * tangent[i], ++i) jacs[i] = jac_storage.data() + off;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.evaluateError(params.data(), r.data(), jacs));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ImuFactorWithoutFactorT);

template <class Factor>
void BM_DynamicsFactorEvaluate(benchmark::State& state) {
  std::mt19937 rng(4);
  std::vector<DynamicsStep> steps(40);
  for (auto& s : steps) s = randomDynamicsStep(rng);
  auto pit = std::make_shared<PreintegratedThrust>(
      PreintegratedThrust::integrate(steps, Vec6::Zero(), ThrustNoiseParams()));
  const DynamicsFactorParams params;
  std::unique_ptr<Factor> f;
  if constexpr (std::is_same_v<Factor, HdvioDynamicsFactor>)
    f = std::make_unique<Factor>(X(0), V(0), F(0), X(1), V(1), F(1), B(0), pit, params);
  else
    f = std::make_unique<Factor>(X(0), V(0), F(0), X(1), V(1), B(0), pit, params);
  const Values v = randomStates(rng);
  runEvaluate(state, *f, v);
}
BENCHMARK_TEMPLATE(BM_DynamicsFactorEvaluate, HdvioDynamicsFactor);
BENCHMARK_TEMPLATE(BM_DynamicsFactorEvaluate, VimoDynamicsFactor);
BENCHMARK_TEMPLATE(BM_DynamicsFactorEvaluate, VidDynamicsFactor);

void BM_ReprojectionFactorEvaluate(benchmark::State& state) {
  const auto model = static_cast<DistortionModel>(state.range(0));
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28, 0.07, 2e-4, 2e-5};
  if (model == DistortionModel::kEquidistant) k = {-0.01, 0.02, -0.01, 0.003};
  const CameraModel cam(752, 480, 458.0, 457.0, 367.0, 248.0, model, k);
  Values v;
  v.insertPose(symbols::X(0), Pose(quatExp(Vec3(0.1, -0.2, 0.3)), Vec3(0.1, 0.2, -0.3)));
  const Pose T_WB = v.pose(symbols::X(0));
  v.insertVector(symbols::L(0), T_WB * Vec3(0.3, -0.2, 4.0));
  ReprojectionFactor f(X(0), L(0), Vec2(300.0, 200.0), cam, Pose(), pixelNoise(1.0));
  runEvaluate(state, f, v);
}
BENCHMARK(BM_ReprojectionFactorEvaluate)->ArgName("distortion")->Arg(0)->Arg(1)->Arg(2);

}  // namespace
}  // namespace hdvio

BENCHMARK_MAIN();
