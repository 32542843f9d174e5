// The IMO reference release's TCN variant (block_relu, window_padding, dilations 2^i) and its
// version-4 weight file: parity with torch through a committed fixture (a tiny randomly
// initialized network of the release's architecture, made by
// scripts/make_imo_release_parity_fixture.py and converted by
// scripts/convert_imo_release_checkpoint.py), no torch needed here.
#include <cmath>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "hdvio/core/error.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {
namespace {

const std::string kData = std::string(HDVIO_SOURCE_DIR) + "/test/learned/data/";

struct Reference {
  std::vector<MatrixXf> windows;  // 6 x samples, rows [thrust; gyro]
  std::vector<Eigen::Vector3f> outputs;  // torch
};

Reference readReference() {
  std::ifstream in(kData + "imo_release_tiny_reference.txt");
  EXPECT_TRUE(in.good()) << "missing imo_release_tiny_reference.txt";
  std::string line;
  auto next = [&]() {
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') return true;
    return false;
  };
  Reference r;
  if (!next()) return r;
  std::istringstream head(line);
  std::string w, s;
  int n = 0, samples = 0;
  head >> w >> n >> s >> samples;
  for (int b = 0; b < n; ++b) {
    MatrixXf x(6, samples);
    for (int row = 0; row < 6 && next(); ++row) {
      std::istringstream ss(line);
      for (int t = 0; t < samples; ++t) ss >> x(row, t);
    }
    Eigen::Vector3f y;
    if (next()) {
      std::istringstream ss(line);
      ss >> y.x() >> y.y() >> y.z();
    }
    r.windows.push_back(x);
    r.outputs.push_back(y);
  }
  return r;
}

TEST(ImoReleaseTcn, ArchitectureOfTheRelease) {
  const TcnArchitecture a = TcnArchitecture::imoRelease();
  EXPECT_TRUE(a.residual && a.block_relu && a.window_padding);
  for (std::size_t l = 0; l < a.layers.size(); ++l) EXPECT_EQ(a.layers[l].dilation, 1 << l);
  EXPECT_EQ(a.receptiveField(), 255);  // 1 + 2 (1 + 2 + ... + 64), on a 50-sample window
  EXPECT_EQ(a.window, 50);
  TcnArchitecture no_padding = a;
  no_padding.window_padding = false;
  EXPECT_THROW(no_padding.validate(), std::invalid_argument);
  TcnArchitecture plain_relu = TcnArchitecture::paper();
  plain_relu.block_relu = true;  // ReLU after a residual sum needs residual blocks
  EXPECT_THROW(plain_relu.validate(), std::invalid_argument);
}

TEST(ImoReleaseTcn, MatchesTorchOnTheCommittedFixture) {
  const DisplacementModel model = DisplacementModel::load(kData + "imo_release_tiny.tcn");
  const TcnArchitecture& a = model.tcn().architecture();
  EXPECT_TRUE(a.block_relu);
  EXPECT_TRUE(a.window_padding);
  EXPECT_GT(a.receptiveField(), a.window);  // 15 > 10: the outputs see the zero padding
  EXPECT_EQ(model.sampleTimes(), DisplacementSampleTimes::kBegin);
  EXPECT_FALSE(model.hasCovariance());
  const Reference ref = readReference();
  ASSERT_EQ(ref.windows.size(), 4u);
  for (std::size_t b = 0; b < ref.windows.size(); ++b) {
    const Eigen::Vector3f y = model.predict(ref.windows[b]).displacement.cast<float>();
    EXPECT_LT((y - ref.outputs[b]).cwiseAbs().maxCoeff(), 1e-5f) << "window " << b << ": " << y.transpose()
                                                                 << " vs torch " << ref.outputs[b].transpose();
    // The pruned windowed path equals the full causal sequence's last step (to float
    // rounding: the dense kernels sum in a different order for other column counts).
    const MatrixXf seq = model.tcn().forwardSequence(ref.windows[b]);
    EXPECT_LT((seq.col(seq.cols() - 1) - y).cwiseAbs().maxCoeff(), 1e-5f) << b;
  }
  // The fixture exercises what it guards: without the block ReLU the outputs move.
  TcnArchitecture no_relu = a;
  no_relu.block_relu = false;
  const Tcn plain(no_relu, model.tcn().weights());
  EXPECT_GT((plain.predictWindow(ref.windows[0]).force - ref.outputs[0]).cwiseAbs().maxCoeff(), 1e-2f);
}

TEST(ImoReleaseTcn, BeginAlignedSampleTimes) {
  const DisplacementModel model = DisplacementModel::load(kData + "imo_release_tiny.tcn");
  const Timestamp t_end = fromSeconds(2.0);
  EXPECT_EQ(model.windowDuration(), fromSeconds(0.1));
  EXPECT_EQ(displacementSampleTime(model, t_end, 0), t_end - fromSeconds(0.1));
  EXPECT_EQ(displacementSampleTime(model, t_end, 9), t_end - fromSeconds(0.01));
  // Constant-rate streams: the window's columns are the samples at those times.
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
  for (int i = 0; i <= 300; ++i) {
    const Timestamp t = fromSeconds(0.01 * i);
    imu.push_back({t, Vec3(0.01 * i, 0, 0), Vec3::Zero()});
    thrust.push_back({t, Vec3(0, 0.01 * i, 9.8)});
  }
  const MatrixXf w = makeDisplacementWindow(model, imu, thrust, t_end,
                                            [](Timestamp) { return Eigen::Quaterniond::Identity(); },
                                            Vec3::Zero(), Vec3::Zero());
  EXPECT_NEAR(w(3, 0), 1.90, 1e-5);  // gyro x at t_end - 0.1 s
  EXPECT_NEAR(w(3, 9), 1.99, 1e-5);
  EXPECT_NEAR(w(1, 9), 1.99, 1e-5);  // thrust y
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/hdvio_imo_release_" + std::to_string(::getpid()) + "_" + name;
}

TEST(ImoReleaseTcn, Version4FileRoundTripAndErrors) {
  const TcnFile f = loadTcnFile(kData + "imo_release_tiny.tcn");
  EXPECT_EQ(f.info.sample_times, "begin");
  EXPECT_TRUE(f.info.output_sigma.empty());
  for (TcnEncoding enc : {TcnEncoding::kText, TcnEncoding::kFloat32}) {
    const std::string text = formatTcnFile(f.tcn, f.info, "", enc);
    EXPECT_EQ(text.rfind("hdvio_tcn 4\n", 0), 0u);
    const TcnFile back = parseTcnFile(text, "mem");
    EXPECT_TRUE(back.tcn.architecture().block_relu);
    EXPECT_TRUE(back.tcn.architecture().window_padding);
    EXPECT_EQ(back.info.sample_times, "begin");
    EXPECT_EQ(back.tcn.weights().conv[0].weight, f.tcn.weights().conv[0].weight);
    EXPECT_EQ(back.tcn.weights().head_bias, f.tcn.weights().head_bias);
  }
  std::ifstream in(kData + "imo_release_tiny.tcn");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  auto expectError = [&](const std::string& from, const std::string& to, const std::string& problem) {
    std::string bad = text;
    const auto pos = bad.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    bad.replace(pos, from.size(), to);
    try {
      parseTcnFile(bad, "bad.tcn");
      ADD_FAILURE() << "accepted " << to;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  };
  expectError("sample_times begin", "sample_times middle", "unknown sample_times");
  expectError("block_relu 1\n", "", "expected \"block_relu\"");
  expectError("window_padding 1", "window_padding 0", "exceeds the window");
  expectError("hdvio_tcn 4", "hdvio_tcn 3", "expected \"input_channels\"");  // v3 has no sample_times
  // A displacement network without covariance loads, but says so.
  const std::string path = tempPath("x.tcn");
  saveTcnFile(f.tcn, f.info, path);
  EXPECT_FALSE(DisplacementModel::load(path).hasCovariance());
  EXPECT_TRUE(DisplacementModel::load(path).predict(MatrixXf::Zero(6, 10)).covariance.isZero(0.0));
  std::remove(path.c_str());
}

}  // namespace
}  // namespace hdvio::learned
