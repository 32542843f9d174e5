// The displacement model (IMO / TLIO-style): version-2 weight files (text and float32), load
// errors, covariance, and the world-frame window builder the filter uses.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unistd.h>
#include <fstream>

#include <gtest/gtest.h>

#include "deterministic_tcn.h"
#include "hdvio/core/error.h"
#include "hdvio/learned/displacement_ensemble.h"
#include "hdvio/learned/displacement_examples.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/learned/residual_force_model.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {
namespace {

TcnFileInfo displacementInfo(const std::string& inputs = "thrust_gyro") {
  TcnFileInfo info;
  info.task = "displacement";
  info.inputs = inputs;
  info.output_sigma = {0.05, 0.06, 0.07};
  return info;
}

void expectSameWeights(const Tcn& a, const Tcn& b) {
  ASSERT_EQ(a.parameterCount(), b.parameterCount());
  EXPECT_EQ(a.architecture().residual, b.architecture().residual);
  const TcnWeights &x = a.weights(), &y = b.weights();
  for (std::size_t i = 0; i < x.conv.size(); ++i) {
    EXPECT_EQ(x.conv[i].weight, y.conv[i].weight) << i;
    EXPECT_EQ(x.conv[i].bias, y.conv[i].bias) << i;
  }
  for (std::size_t i = 0; i < x.skip.size(); ++i) EXPECT_EQ(x.skip[i].weight, y.skip[i].weight) << i;
  EXPECT_EQ(x.head_weight, y.head_weight);
  EXPECT_EQ(x.input_std, y.input_std);
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/hdvio_displacement_" + std::to_string(::getpid()) + "_" + name;
}

TEST(DisplacementWeightFile, TextAndFloat32RoundTripsAreExact) {
  const Tcn tcn = testing::deterministicResidualTcn();
  for (TcnEncoding enc : {TcnEncoding::kText, TcnEncoding::kFloat32}) {
    const std::string text = formatTcnFile(tcn, displacementInfo("accel_gyro"), "a comment\nline 2", enc);
    EXPECT_EQ(text.rfind("hdvio_tcn 2\n# a comment\n# line 2\ntask displacement\n", 0), 0u);
    const TcnFile back = parseTcnFile(text, "x.tcn");
    expectSameWeights(tcn, back.tcn);
    EXPECT_EQ(back.info.task, "displacement");
    EXPECT_EQ(back.info.inputs, "accel_gyro");
    ASSERT_EQ(back.info.output_sigma.size(), 3u);
    EXPECT_DOUBLE_EQ(back.info.output_sigma[2], 0.07);
  }
  // float32 is compact: 4 bytes per parameter plus a short header.
  const std::size_t bytes = formatTcnFile(tcn, displacementInfo(), "", TcnEncoding::kFloat32).size();
  EXPECT_LT(bytes, 4 * (tcn.parameterCount() + 12) + 600);
}

TEST(DisplacementWeightFile, PlainNetworksStillWriteVersion1) {
  const std::string text = formatTcnWeights(testing::deterministicTcn());
  EXPECT_EQ(text.rfind("hdvio_tcn 1\n", 0), 0u);
  const TcnFile f = parseTcnFile(text, "v1.tcn");
  EXPECT_EQ(f.info.task, "force");
  EXPECT_TRUE(f.info.output_sigma.empty());
  // A residual network through the old entry point gets version 2 with default info.
  const std::string v2 = formatTcnWeights(testing::deterministicResidualTcn());
  EXPECT_EQ(v2.rfind("hdvio_tcn 2\n", 0), 0u);
  expectSameWeights(parseTcnWeights(v2, "v2.tcn"), testing::deterministicResidualTcn());
}

void expectFailure(const std::string& text, long line, const std::string& fragment) {
  try {
    parseTcnFile(text, "bad.tcn");
    ADD_FAILURE() << "no error for: " << fragment;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "bad.tcn");
    if (line >= 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(DisplacementWeightFile, MalformedVersion2) {
  const Tcn tcn = testing::deterministicResidualTcn();
  const std::string text = formatTcnFile(tcn, displacementInfo(), "", TcnEncoding::kText);
  expectFailure(replaced(text, "task displacement", "task speed"), 2, "unknown task 'speed'");
  expectFailure(replaced(text, "inputs thrust_gyro", "inputs thrust"), 3, "unknown inputs");
  expectFailure(replaced(text, "output_sigma 0.05", "output_sigma -0.05"), 4, "output_sigma must be positive");
  expectFailure(replaced(text, "residual 1", "residual 2"), 10, "out of range");
  expectFailure(replaced(text, "encoding text", "encoding zip"), -1, "unknown encoding");
  expectFailure(replaced(text, "matrix skip4.weight", "matrix skip5.weight"), -1, "expected \"matrix skip4.weight");

  const std::string bin = formatTcnFile(tcn, displacementInfo(), "", TcnEncoding::kFloat32);
  const auto data = bin.find("data ");
  expectFailure(bin.substr(0, data + 500), -1, "inside the float32 data");
  const std::string count = std::to_string(tcn.parameterCount() + 12);  // + input mean and std
  expectFailure(replaced(bin, "data " + count, "data " + std::to_string(tcn.parameterCount() + 13)), -1,
                "float32 data");
  std::string nan = bin;
  const float q = std::nanf("");
  std::memcpy(&nan[bin.find('\n', data) + 1 + 4 * 20], &q, 4);  // a weight of conv0
  expectFailure(nan, -1, "conv0.weight holds a non-finite float");
  expectFailure(bin + "end\n", -1, "after \"end\"");
}

// Version 3: a force network with the drag law it complements; the law reaches the model.
TEST(ForceWeightFile, Version3CarriesTheDragLaw) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.25, 0.05);
  info.drag_law.quadratic = Vec3(0.01, 0.0, 0.02);
  const std::string text = formatTcnFile(tcn, info);
  EXPECT_EQ(text.rfind("hdvio_tcn 3\n", 0), 0u);
  EXPECT_NE(text.find("\ndrag_law 0.3 0.25 0.05 0.01 0 0.02\n"), std::string::npos);
  const TcnFile back = parseTcnFile(text, "v3.tcn");
  EXPECT_EQ(back.info.drag_law.linear, info.drag_law.linear);
  EXPECT_EQ(back.info.drag_law.quadratic, info.drag_law.quadratic);
  expectSameWeights(back.tcn, tcn);
  const std::string path = tempPath("v3.tcn");
  saveTcnFile(tcn, info, path);
  const auto model = ResidualForceModel::load(path, 0.3);
  EXPECT_EQ(model->dragLaw().linear, info.drag_law.linear);
  std::remove(path.c_str());
  // Without a law the file stays version 2, and a version-2 file has no law.
  const std::string v2 = formatTcnFile(tcn, TcnFileInfo());
  EXPECT_EQ(v2.rfind("hdvio_tcn 2\n", 0), 0u);
  EXPECT_FALSE(parseTcnFile(v2, "v2.tcn").info.drag_law.enabled());

  expectFailure(replaced(text, "drag_law 0.3 0.25 0.05 0.01 0 0.02", "drag_law 0.3 -0.25 0.05 0.01 0 0.02"),
                5, "drag_law coefficients must be non-negative");
  expectFailure(replaced(text, "drag_law 0.3 0.25 0.05 0.01 0 0.02", "drag_law 0.3 0.25"), 5,
                "drag_law <dx> <dy> <dz> <cx> <cy> <cz>");
  expectFailure(replaced(text, "drag_law 0.3 0.25 0.05 0.01 0 0.02\n", ""), 5, "drag_law");
}

// The rotor and lift terms and the law's residual sigma extend the same line; a version-3 line
// with only the six original numbers (above) still reads, with those terms zero.
TEST(ForceWeightFile, Version3CarriesRotorLiftAndSigma) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.quadratic = Vec3(0.0, 0.0108, 0.0469);
  info.drag_law.rotor = Vec3(0.242, 0.187, 0.068);
  info.drag_law.lift = 0.0164;
  info.drag_law.sigma = Vec3(0.63, 0.49, 1.03);
  const std::string text = formatTcnFile(tcn, info);
  EXPECT_EQ(text.rfind("hdvio_tcn 3\n", 0), 0u);
  const std::string line = "drag_law 0 0 0 0 0.0108 0.0469 0.242 0.187 0.068 0.0164 0.63 0.49 1.03";
  EXPECT_NE(text.find("\n" + line + "\n"), std::string::npos) << text.substr(0, 300);
  const DragLaw back = parseTcnFile(text, "v3.tcn").info.drag_law;
  EXPECT_EQ(back.rotor, info.drag_law.rotor);
  EXPECT_EQ(back.lift, info.drag_law.lift);
  EXPECT_EQ(back.sigma, info.drag_law.sigma);
  EXPECT_EQ(back.quadratic, info.drag_law.quadratic);
  expectFailure(replaced(text, line, "drag_law 0 0 0 0 0.0108 0.0469 0.242 0.187 0.068 -0.0164 0.63 0.49 1.03"), 5,
                "drag_law coefficients must be non-negative");
  expectFailure(replaced(text, line, "drag_law 0 0 0 0 0.0108 0.0469 0.242 0.187 0.068 0.0164"), 5,
                "drag_law <dx> <dy> <dz> <cx> <cy> <cz> [<rx> <ry> <rz> <lift> <sx> <sy> <sz> "
                "[<speed x y z> <rate x y z> <thrust x y z>]]");
}

// A sigma that grows with speed, body rate and thrust appends its nine coefficients (22 numbers).
TEST(ForceWeightFile, Version3CarriesASigmaThatGrows) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.rotor = Vec3(0.242, 0.187, 0.068);
  info.drag_law.sigma = Vec3(0.037, 0.056, 0.17);
  info.drag_law.sigma_speed = Vec3(0.03, 0.013, 0.0);
  info.drag_law.sigma_rate = Vec3(0.23, 0.26, 0.51);
  info.drag_law.sigma_thrust = Vec3(0.027, 0.013, 0.076);
  const std::string text = formatTcnFile(tcn, info);
  const std::string line =
      "drag_law 0 0 0 0 0 0 0.242 0.187 0.068 0 0.037 0.056 0.17 0.03 0.013 0 0.23 0.26 0.51 0.027 0.013 0.076";
  EXPECT_NE(text.find("\n" + line + "\n"), std::string::npos) << text.substr(0, 300);
  const DragLaw back = parseTcnFile(text, "v3.tcn").info.drag_law;
  EXPECT_EQ(back.sigma, info.drag_law.sigma);
  EXPECT_EQ(back.sigma_speed, info.drag_law.sigma_speed);
  EXPECT_EQ(back.sigma_rate, info.drag_law.sigma_rate);
  EXPECT_EQ(back.sigma_thrust, info.drag_law.sigma_thrust);
  expectFailure(replaced(text, line, line.substr(0, line.size() - 6)), 5, "drag_law <dx>");
  expectFailure(replaced(text, line, line.substr(0, line.size() - 5) + "-0.076"), 5,
                "drag_law coefficients must be non-negative");
}

// Version 5: the walk of the model's held-out error reaches the model (and the estimator).
TEST(ForceWeightFile, Version5CarriesTheModelErrorWalk) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.0);
  info.force_walk = 0.21;
  const std::string text = formatTcnFile(tcn, info);
  EXPECT_EQ(text.rfind("hdvio_tcn 5\n", 0), 0u);
  EXPECT_NE(text.find("\nsample_times end\nforce_walk 0.21\n"), std::string::npos) << text.substr(0, 300);
  EXPECT_EQ(parseTcnFile(text, "v5.tcn").info.force_walk, 0.21);
  const std::string path = tempPath("v5.tcn");
  saveTcnFile(tcn, info, path);
  EXPECT_EQ(ResidualForceModel::load(path, 0.3)->forceWalk(), 0.21);
  std::remove(path.c_str());
  // No walk: the file stays version 3, and reads as walk 0.
  info.force_walk = 0.0;
  const std::string v3 = formatTcnFile(tcn, info);
  EXPECT_EQ(v3.rfind("hdvio_tcn 3\n", 0), 0u);
  EXPECT_EQ(parseTcnFile(v3, "v3.tcn").info.force_walk, 0.0);
  expectFailure(replaced(text, "force_walk 0.21", "force_walk -0.2"), 7, "force_walk must be non-negative");
  expectFailure(replaced(text, "force_walk 0.21\n", ""), 7, "force_walk");
}

// Version 6: a network trained on an estimator's trajectory says so; ground truth stays 5.
TEST(ForceWeightFile, Version6RecordsSupervisionByAnEstimate) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.0);
  info.supervision = "estimate";
  const std::string text = formatTcnFile(tcn, info);
  EXPECT_EQ(text.rfind("hdvio_tcn 6\n", 0), 0u);
  EXPECT_NE(text.find("\nforce_walk 0\nsupervision estimate\n"), std::string::npos) << text.substr(0, 300);
  EXPECT_EQ(parseTcnFile(text, "v6.tcn").info.supervision, "estimate");
  info.supervision = "groundtruth";
  info.force_walk = 0.21;
  EXPECT_EQ(formatTcnFile(tcn, info).rfind("hdvio_tcn 5\n", 0), 0u);
  EXPECT_EQ(parseTcnFile(formatTcnFile(tcn, info), "v5.tcn").info.supervision, "groundtruth");
  expectFailure(replaced(text, "supervision estimate", "supervision slam"), 8, "unknown supervision 'slam'");
  expectFailure(replaced(text, "supervision estimate\n", ""), 8, "supervision");
}

// Version 7: what the training samples held reaches the model (and the estimator).
TEST(ForceWeightFile, Version7CarriesTheTrainingEnvelope) {
  const Tcn tcn = testing::deterministicTcn();
  TcnFileInfo info;
  info.drag_law.linear = Vec3(0.3, 0.3, 0.0);
  info.force_walk = 0.21;
  info.envelope.speed_max = 9.16;
  info.envelope.rate_max = 1.35;
  info.envelope.thrust_min = 8.97;
  info.envelope.thrust_max = 13.4;
  const std::string text = formatTcnFile(tcn, info);
  EXPECT_EQ(text.rfind("hdvio_tcn 7\n", 0), 0u);
  EXPECT_NE(text.find("\nsupervision groundtruth\nenvelope 9.16 1.35 8.97 13.4\n"), std::string::npos)
      << text.substr(0, 300);
  const std::string path = tempPath("v7.tcn");
  saveTcnFile(tcn, info, path);
  const ModelEnvelope back = ResidualForceModel::load(path, 0.3)->envelope();
  std::remove(path.c_str());
  EXPECT_EQ(back.speed_max, 9.16);
  EXPECT_EQ(back.rate_max, 1.35);
  EXPECT_EQ(back.thrust_min, 8.97);
  EXPECT_EQ(back.thrust_max, 13.4);
  // A partial envelope cannot be written (the reader needs all four bounds).
  ModelEnvelope partial;
  partial.speed_max = 9.16;
  TcnFileInfo partial_info = info;
  partial_info.envelope = partial;
  EXPECT_THROW(formatTcnFile(tcn, partial_info), std::invalid_argument);
  // Without one the file stays version 5 and reads as unbounded.
  info.envelope = ModelEnvelope();
  const std::string v5 = formatTcnFile(tcn, info);
  EXPECT_EQ(v5.rfind("hdvio_tcn 5\n", 0), 0u);
  EXPECT_TRUE(parseTcnFile(v5, "v5.tcn").info.envelope.unbounded());
  expectFailure(replaced(text, "envelope 9.16 1.35 8.97 13.4", "envelope 9.16 1.35 13.4 8.97"), 9,
                "envelope needs positive speed_max");
  expectFailure(replaced(text, "envelope 9.16 1.35 8.97 13.4", "envelope 9.16 1.35"), 9, "envelope <speed_max>");
  expectFailure(replaced(text, "envelope 9.16 1.35 8.97 13.4\n", ""), 9, "envelope");
}

TEST(DisplacementModel, LoadChecksTaskAndSigma) {
  const std::string path = tempPath("model.tcn");
  saveTcnFile(testing::deterministicResidualTcn(), displacementInfo("accel_gyro"), path, "", TcnEncoding::kFloat32);
  const DisplacementModel m = DisplacementModel::load(path);
  EXPECT_EQ(m.inputKind(), DisplacementInputKind::kAccelGyro);
  EXPECT_EQ(m.windowSamples(), 50);
  EXPECT_DOUBLE_EQ(m.sampleRateHz(), 100.0);
  EXPECT_DOUBLE_EQ(m.windowSeconds(), 0.5);
  const DisplacementPrediction p = m.predict(testing::deterministicInputs(50));
  const TcnOutput direct = testing::deterministicResidualTcn().predictWindow(testing::deterministicInputs(50));
  EXPECT_NEAR((p.displacement - direct.force.cast<double>()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(p.covariance(1, 1), 0.06 * 0.06, 1e-12);
  EXPECT_EQ(p.covariance(0, 1), 0.0);
  EXPECT_THROW(m.predict(testing::deterministicInputs(49)), std::invalid_argument);

  TcnFileInfo no_sigma = displacementInfo();
  no_sigma.output_sigma.clear();
  saveTcnFile(testing::deterministicResidualTcn(), no_sigma, path);
  EXPECT_FALSE(DisplacementModel::load(path).hasCovariance());  // "output_sigma none"
  EXPECT_TRUE(m.hasCovariance());
  saveTcnWeights(testing::deterministicTcn(), path);  // a residual-force network
  try {
    DisplacementModel::load(path);
    ADD_FAILURE() << "loaded a force network as a displacement model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a displacement network"), std::string::npos) << e.what();
  }
  EXPECT_THROW(DisplacementModel::load(tempPath("missing.tcn")), InputError);
  // ... and the residual-force model refuses a displacement network.
  saveTcnFile(testing::deterministicResidualTcn(), displacementInfo(), path);
  EXPECT_THROW(ResidualForceModel::load(path, 0.1), InputError);
  std::remove(path.c_str());
}

// A tiny model (window 5 at 100 Hz) for the window builder; with its zero convolutions it
// predicts `displacement` for every window.
DisplacementModel tinyModel(DisplacementInputKind kind, const Eigen::Vector3f& displacement = Eigen::Vector3f::Zero(),
                            std::optional<Eigen::Vector3d> sigma = Eigen::Vector3d::Constant(0.1), int window = 5) {
  TcnArchitecture a;
  a.residual = true;
  a.window = window;
  a.layers = {{3, 1}};
  TcnWeights w;
  w.input_mean = VectorXf::Zero(6);
  w.input_std = VectorXf::Ones(6);
  w.conv = {{MatrixXf::Zero(3, 12), VectorXf::Zero(3)}, {MatrixXf::Zero(3, 6), VectorXf::Zero(3)}};
  w.skip = {{MatrixXf::Zero(3, 6), VectorXf::Zero(3)}};
  w.head_weight = MatrixXf::Identity(3, 3);
  w.head_bias = displacement;
  return DisplacementModel(Tcn(a, w), kind, sigma);
}

TEST(DisplacementEnsemble, MeanDisplacementAndTheMixturesCovariance) {
  using K = DisplacementInputKind;
  const MatrixXf window = MatrixXf::Ones(6, 5);
  TcnWorkspace workspace;
  const DisplacementEnsemble one({tinyModel(K::kThrustGyro, {1.0f, 2.0f, 3.0f})});
  const DisplacementPrediction p1 = one.predict(window, &workspace);
  const DisplacementPrediction m1 = tinyModel(K::kThrustGyro, {1.0f, 2.0f, 3.0f}).predict(window);
  EXPECT_EQ(p1.displacement, m1.displacement);  // one member: that network, unchanged
  EXPECT_EQ(p1.covariance, m1.covariance);

  const DisplacementEnsemble two({tinyModel(K::kThrustGyro, {1.0f, 0.0f, 0.0f}),
                                  tinyModel(K::kThrustGyro, {3.0f, 0.0f, 0.0f}, Eigen::Vector3d(0.3, 0.1, 0.1))});
  const DisplacementPrediction p = two.predict(window, &workspace);
  EXPECT_NEAR((p.displacement - Vec3(2.0, 0.0, 0.0)).norm(), 0.0, 1e-6);
  // Members' mean variance (0.01 + 0.09) / 2 plus their spread around the mean (1 + 1) / 2.
  EXPECT_NEAR(p.covariance(0, 0), 0.05 + 1.0, 1e-6);
  EXPECT_NEAR(p.covariance(1, 1), 0.01, 1e-9);
  EXPECT_NEAR(p.covariance(0, 1), 0.0, 1e-9);
  EXPECT_EQ(two.size(), 2);
  EXPECT_TRUE(two.hasCovariance());

  // Members without covariance: the mean, no covariance (the filter's own sigma then).
  const DisplacementEnsemble bare({tinyModel(K::kThrustGyro, {1.0f, 0.0f, 0.0f}, std::nullopt),
                                   tinyModel(K::kThrustGyro, {3.0f, 0.0f, 0.0f}, std::nullopt)});
  EXPECT_FALSE(bare.hasCovariance());
  EXPECT_EQ(bare.predict(window, &workspace).covariance, Eigen::Matrix3d::Zero());

  // Members must read the same window and agree on having a covariance.
  EXPECT_THROW(DisplacementEnsemble({}), std::invalid_argument);
  EXPECT_THROW(DisplacementEnsemble({tinyModel(K::kThrustGyro), tinyModel(K::kAccelGyro)}), std::invalid_argument);
  EXPECT_THROW(DisplacementEnsemble({tinyModel(K::kThrustGyro), tinyModel(K::kThrustGyro, Eigen::Vector3f::Zero(), Eigen::Vector3d::Constant(0.1), 6)}),
               std::invalid_argument);
  EXPECT_THROW(DisplacementEnsemble({tinyModel(K::kThrustGyro), tinyModel(K::kThrustGyro, Eigen::Vector3f::Zero(), std::nullopt)}),
               std::invalid_argument);
}

// Signals linear in time, so linear interpolation is exact.
Vec3 gyroAt(double s) { return Vec3(0.1 + s, -0.2 * s, 0.3); }
Vec3 accelAt(double s) { return Vec3(1.0 - s, 0.5, 9.8 + 2.0 * s); }
Vec3 thrustAt(double s) { return Vec3(0.2 * s, -0.1, 9.0 + s); }
Eigen::Quaterniond attitude(Timestamp t) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(0.8 * toSeconds(t), Vec3(0.2, -0.3, 1.0).normalized()));
}

struct Streams {
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
};

// IMU at 400 Hz from 1.0 s, thrust at 100 Hz from 1.003 s (another clock phase), to 3 s.
Streams streams() {
  Streams s;
  for (Timestamp t = fromSeconds(1.0); t <= fromSeconds(3.0); t += 2500000) {
    s.imu.push_back({t, gyroAt(toSeconds(t)), accelAt(toSeconds(t))});
  }
  for (Timestamp t = fromSeconds(1.003); t <= fromSeconds(3.0); t += 10000000) {
    s.thrust.push_back({t, thrustAt(toSeconds(t))});
  }
  return s;
}

TEST(DisplacementWindow, RotatesInterpolatesAndRemovesBiases) {
  const Streams s = streams();
  const Vec3 bg(0.01, -0.02, 0.03), ba(0.1, 0.2, -0.3);
  const Timestamp t_end = fromSeconds(2.0071);
  for (auto kind : {DisplacementInputKind::kThrustGyro, DisplacementInputKind::kAccelGyro}) {
    const DisplacementModel m = tinyModel(kind);
    const MatrixXf w = makeDisplacementWindow(m, s.imu, s.thrust, t_end, attitude, bg, ba);
    ASSERT_EQ(w.rows(), 6);
    ASSERT_EQ(w.cols(), 5);
    for (int k = 0; k < 5; ++k) {
      const Timestamp t = displacementSampleTime(m, t_end, k);
      EXPECT_EQ(t, t_end - fromSeconds(0.01 * (4 - k)));
      const double sec = toSeconds(t);
      const Eigen::Matrix3d R = attitude(t).toRotationMatrix();
      const Vec3 f = kind == DisplacementInputKind::kThrustGyro ? thrustAt(sec) : Vec3(accelAt(sec) - ba);
      EXPECT_LT((w.col(k).head<3>().cast<double>() - R * f).norm(), 1e-5) << k;
      EXPECT_LT((w.col(k).tail<3>().cast<double>() - R * (gyroAt(sec) - bg)).norm(), 1e-5) << k;
    }
  }
}

TEST(DisplacementWindow, RequiresCoverageOfTheWholeWindow) {
  const Streams s = streams();
  const DisplacementModel imo = tinyModel(DisplacementInputKind::kThrustGyro);
  const DisplacementModel tlio = tinyModel(DisplacementInputKind::kAccelGyro);
  const Vec3 z = Vec3::Zero();
  // Window [t_end - 0.05 s, t_end]: IMU from 1.0 s, thrust from 1.003 s, both to 3.0 s.
  EXPECT_NO_THROW(makeDisplacementWindow(tlio, s.imu, {}, fromSeconds(1.05), attitude, z, z));
  EXPECT_THROW(makeDisplacementWindow(tlio, s.imu, {}, fromSeconds(1.049), attitude, z, z), InputError);
  EXPECT_THROW(makeDisplacementWindow(imo, s.imu, s.thrust, fromSeconds(1.051), attitude, z, z), InputError);
  EXPECT_NO_THROW(makeDisplacementWindow(imo, s.imu, s.thrust, fromSeconds(1.053), attitude, z, z));
  EXPECT_THROW(makeDisplacementWindow(imo, s.imu, s.thrust, fromSeconds(3.001), attitude, z, z), InputError);
  EXPECT_THROW(makeDisplacementWindow(imo, s.imu, {}, fromSeconds(2.0), attitude, z, z), InputError);
  EXPECT_THROW(makeDisplacementWindow(imo, {}, s.thrust, fromSeconds(2.0), attitude, z, z), InputError);
}

// The training examples use the same convention as the window builder: window ending at
// sample `end` holds samples end-W+1..end, the target spans exactly W samples.
TEST(DisplacementExamples, WindowTargetAndIntegratedReference) {
  FlightSamples f;
  f.name = "synthetic";
  f.rate_hz = 100.0;
  const Vec3 acc(0.5, -1.0, 2.0);  // constant world acceleration, level attitude
  for (int k = 0; k < 40; ++k) {
    const double s = k / 100.0;
    f.t.push_back(fromSeconds(s));
    f.p_W.push_back(Vec3(1, 2, 3) + Vec3(0.3, 0.0, -0.1) * s + 0.5 * acc * s * s);
    f.v_W.push_back(Vec3(0.3, 0.0, -0.1) + acc * s);
    f.q_WB.push_back(Quat::Identity());
    f.thrust.push_back(acc - gravityWorld());
    f.force.push_back(acc - gravityWorld());
    f.gyro.push_back(Vec3(0.0, 0.0, 0.01 * k));
  }
  const auto ex = displacementExamples({f}, 5, 3);
  ASSERT_EQ(ex.size(), 12u);  // ends 5, 8, ..., 38
  EXPECT_EQ(ex.front().end, 5u);
  const Vec3 target = displacementTarget(f, 20, 5);
  EXPECT_LT((target - (f.p_W[20] - f.p_W[15])).norm(), 1e-12);
  // Exact for constant acceleration (the integrator is the trapezoid-free exact update).
  EXPECT_LT((integratedDisplacement(f, 20, 5, DisplacementInputKind::kThrustGyro) - target).norm(), 1e-9);
  const MatrixXf w = worldWindow(f, 20, 5, DisplacementInputKind::kThrustGyro);
  EXPECT_NEAR(w(5, 4), 0.2f, 1e-6);  // gyro z of sample 20
  EXPECT_NEAR(w(5, 0), 0.16f, 1e-6);  // sample 16
  EXPECT_THROW(worldWindow(f, 4, 5, DisplacementInputKind::kThrustGyro), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
