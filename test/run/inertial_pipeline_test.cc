// hdvio_run's inertial methods on the real Blackbird validation flight (the Model-EKF, the
// shipped networks), and bad inputs (missing thrust, ground truth or weights) are InputErrors.
// The estimator alone: test/imo/imo_streaming_test.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../common/blackbird_val.h"
#include "hdvio/core/error.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/run/method_pipeline.h"

namespace hdvio::run {
namespace {

const ExperimentFile kFile{"test.yaml", ""};

std::unique_ptr<MethodPipeline> make(const std::string& method, const std::string& yaml) {
  const ConfigReader cfg = ConfigReader::fromString(yaml, "test.yaml");
  std::string m;
  cfg.read("method", &m);  // hdvio_run reads it before dispatching
  auto p = makeInertialPipeline(method, cfg, kFile);
  cfg.finish();
  return p;
}

using test::blackbirdVal;
using test::kBlackbirdVal;
using test::positionRmse;

// The Model-EKF through hdvio_run's pipeline with the shipped config (thrust + linear drag
// fitted on the Blackbird *train* flight) on the whole validation flight, without alignment:
// the drag term gives the filter velocity, so it stays bounded, while the thrust-only model
// (no drag, k = 1) drifts like dead reckoning (docs/imo.md).
TEST(ImoPipeline, ModelEkfWithDragTracksBlackbirdValidationFlight) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  const Sequence& seq = blackbirdVal();
  std::ifstream in(std::string(HDVIO_SOURCE_DIR) + "/config/experiments/model_ekf.yaml");
  const std::string shipped((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(shipped.empty());
  auto pipeline = make("model_ekf", shipped);
  const RunResults r = pipeline->run(seq);
  ASSERT_GT(r.states.size(), 2900u);  // 30 s at 100 Hz
  double max_err = 0.0;
  const double rmse = positionRmse(seq, r.states, &max_err);
  std::printf("model_ekf (drag) on Blackbird val: position RMSE %.3f m, max %.3f m\n", rmse, max_err);
  EXPECT_LT(rmse, MODEL_EKF_RMSE_TOLERANCE) << "max " << max_err;
  ASSERT_EQ(r.stages.size(), 3u);
  EXPECT_EQ(r.stages[0].stage, "propagation");
  EXPECT_EQ(r.stages[1].stage, "model");

  auto thrust_only = make("model_ekf", "method: model_ekf\nmodel: {attitude_jacobian: true}\n");
  const RunResults d = thrust_only->run(seq);
  double max_d = 0.0;
  const double rmse_d = positionRmse(seq, d.states, &max_d);
  std::printf("model_ekf (thrust only) on Blackbird val: position RMSE %.3f m, max %.3f m\n", rmse_d, max_d);
  EXPECT_GT(rmse_d, 3.0 * rmse);
}

// The shipped networks (learned/models/, never trained on this flight) through hdvio_run's
// pipeline on the whole Blackbird validation flight, started from the first ground-truth state
// and compared without alignment. IMU-only dead reckoning drifts by tens of metres here.
TEST(ImoPipeline, ShippedNetworksTrackTheBlackbirdValidationFlight) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  const Sequence& seq = blackbirdVal();
  for (const std::string method : {"imo", "tlio"}) {
    const std::string weights =
        std::string(HDVIO_SOURCE_DIR) + "/learned/models/" + method + "_blackbird.tcn";
    auto pipeline = make(method, "method: " + method + "\nnetwork: {weights: " + weights +
                                     "}\nfilter: {use_source_covariance: true}\n");
    const RunResults r = pipeline->run(seq);
    ASSERT_GT(r.states.size(), 2900u) << method;  // 30 s at 100 Hz
    double max_err = 0.0;
    const double rmse = positionRmse(seq, r.states, &max_err);
    EXPECT_LT(rmse, IMO_SHIPPED_RMSE_TOLERANCE) << method << ", max " << max_err;
  }
}

TEST(ImoPipeline, MissingThrustIsAnInputError) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  Sequence seq = blackbirdVal();
  seq.thrust.clear();
  auto pipeline = make("model_ekf", "method: model_ekf\n");
  EXPECT_THROW(pipeline->run(seq), InputError);
}

TEST(ImoPipeline, MissingGroundTruthIsAnInputError) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  Sequence seq = blackbirdVal();
  seq.groundtruth.clear();
  auto pipeline = make("model_ekf", "method: model_ekf\n");
  EXPECT_THROW(pipeline->run(seq), InputError);
}

TEST(ImoPipeline, MissingWeightsFileIsAnInputError) {
  for (const std::string method : {"imo", "tlio", "net_only"}) {
    try {
      make(method, "method: " + method + "\nnetwork: {weights: /nonexistent/imo.tcn}\n");
      ADD_FAILURE() << method << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("/nonexistent/imo.tcn"), std::string::npos) << e.what();
    }
    // The network section is required.
    EXPECT_THROW(make(method, "method: " + method + "\n"), InputError) << method;
  }
}

TEST(ImoPipeline, BadConfigValuesAreInputErrors) {
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {measurement_sigma: [0.1, 0, 0.1]}\n"),
               InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {update_rate_hz: 7}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nthrust: {axis: [0, 0, 2]}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {no_such_key: 1}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nmodel: {linear_drag: [0.3, -0.1, 0.2]}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nmodel: {thrust_scale: 0}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nmodel: {linear_drag: [0.3, 0.2]}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {rotation_error: world}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {gravity: 98.1}\n"), InputError);
  EXPECT_THROW(make("model_ekf", "method: model_ekf\nfilter: {release_first_window_sample: maybe}\n"), InputError);
  EXPECT_NO_THROW(make("model_ekf", "method: model_ekf\nfilter: {rotation_error: left, gravity: 9.8082}\n"));
}

// release_first_window_sample: the network windows see the start sample with the next
// sample's values (exactly as a stream where it was replaced), and only windows containing it.
TEST(ImoPipeline, ReleaseFirstWindowSampleRepeatsTheSecondSampleInTheFirstWindowOnly) {
  const auto model = std::make_shared<const learned::DisplacementModel>(learned::DisplacementModel::load(
      std::string(HDVIO_SOURCE_DIR) + "/test/learned/data/imo_release_tiny.tcn"));
  Sequence seq, replaced;
  std::vector<ThrustSample> thrust, thrust_replaced;
  const Timestamp t0 = fromSeconds(2.0), dt = fromSeconds(1.0 / model->sampleRateHz());
  for (int k = 0; k < 3 * model->windowSamples(); ++k) {
    const double x = 0.37 * k;
    seq.imu.push_back({t0 + k * dt, Vec3(std::sin(x), std::cos(x), 0.2 * x), Vec3(0.1, -0.3, 9.8)});
    thrust.push_back({t0 + k * dt, Vec3(0.5 * std::cos(x), 0.2, 9.5 + std::sin(x))});
  }
  replaced.imu = seq.imu;
  thrust_replaced = thrust;
  replaced.imu[0] = seq.imu[1];
  replaced.imu[0].t = t0;
  thrust_replaced[0] = thrust[1];
  thrust_replaced[0].t = t0;
  auto shared = [](const auto& v) { return std::make_shared<const std::decay_t<decltype(v)>>(v); };
  const auto repeating = networkDisplacementSource(model, shared(seq.imu), shared(thrust), t0);
  const auto plain = networkDisplacementSource(model, shared(seq.imu), shared(thrust));
  const auto reference = networkDisplacementSource(model, shared(replaced.imu), shared(thrust_replaced));
  auto request = [&](Timestamp t_end) {
    imo::DisplacementRequest r;
    r.t_end = t_end;
    r.t_begin = t_end - model->windowDuration();
    r.world_from_body = [](Timestamp) { return Quat(Eigen::AngleAxisd(0.4, Vec3(0.3, -0.5, 0.8).normalized())); };
    return r;
  };
  const imo::DisplacementRequest first = request(t0 + model->windowDuration());
  const imo::DisplacementRequest second = request(t0 + model->windowDuration() + dt);
  ASSERT_TRUE(repeating(first) && plain(first) && reference(first));
  EXPECT_EQ(repeating(first)->z, reference(first)->z);
  EXPECT_GT((repeating(first)->z - plain(first)->z).norm(), 1e-6);
  EXPECT_EQ(repeating(second)->z, plain(second)->z);
}

// A network without covariance (the IMO release's, output_sigma none) needs the filter's sigma.
TEST(ImoPipeline, SourceCovarianceFromANetworkWithoutOneIsAnInputError) {
  const std::string net = "network: {weights: " + std::string(HDVIO_SOURCE_DIR) +
                          "/test/learned/data/imo_release_tiny.tcn}\n";
  EXPECT_NO_THROW(make("imo", "method: imo\n" + net + "filter: {use_source_covariance: false}\n"));
  try {
    make("imo", "method: imo\n" + net + "filter: {use_source_covariance: true}\n");
    ADD_FAILURE() << "accepted use_source_covariance without a covariance";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no covariance"), std::string::npos) << e.what();
  }
}

// The shipped DIDO configs (imo_dido.yaml, tlio_dido.yaml, net_only_dido.yaml) name networks that exist and read
// one window (the DIDO flights themselves are outside the repository).
TEST(ImoPipeline, ShippedDidoEnsembleConfigsBuild) {
  const std::string dir = std::string(HDVIO_SOURCE_DIR) + "/config/experiments";
  for (const std::string method : {"imo", "tlio", "net_only"}) {
    const std::string path = dir + "/" + method + "_dido.yaml";
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(text.empty()) << path;
    const ConfigReader cfg = ConfigReader::fromString(text, path);
    std::string m;
    cfg.read("method", &m);
    EXPECT_NO_THROW(makeInertialPipeline(method, cfg, {path, dir})) << path;
  }
}

// network.ensemble: networks of one recipe as one source; exactly one of weights and ensemble,
// members that read the same window.
TEST(ImoPipeline, NetworkEnsembleKeysAreChecked) {
  const std::string models = std::string(HDVIO_SOURCE_DIR) + "/learned/models/";
  const std::string dido = models + "imo_dido_1.tcn, " + models + "imo_dido_2.tcn";
  EXPECT_NO_THROW(make("imo", "method: imo\nnetwork: {ensemble: [" + dido + "]}\n"));
  const auto expectError = [](const std::string& yaml, const std::string& what) {
    try {
      make("imo", yaml);
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test.yaml:2"), std::string::npos) << e.what();
    }
  };
  expectError("method: imo\nnetwork: {weights: " + models + "imo_dido_1.tcn, ensemble: [" + dido + "]}\n",
              "exactly one of weights");
  expectError("method: imo\nnetwork: {}\n", "exactly one of weights");
  expectError("method: imo\nnetwork: {ensemble: []}\n", "the list is empty");
  expectError("method: imo\nnetwork: {ensemble: [" + dido + ", " + models + "tlio_dido_1.tcn]}\n",
              "member 3 reads another window");
}

}  // namespace
}  // namespace hdvio::run
