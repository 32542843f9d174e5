// Depth filters converge on a flight rendered by hdvio_sim (config/sim/ci_tiny.yaml): the
// converged points must lie on the walls of the simulated room.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "hdvio/frontend/depth_filter.h"
#include "hdvio/frontend/feature_detector.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"

namespace hdvio::frontend {
namespace {

// ci_tiny.yaml: scene.room_min / room_max.
const Vec3 kRoomMin(-4.0, -3.0, 0.0), kRoomMax(4.0, 3.0, 3.0);

double distanceToWalls(const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) d = std::min({d, std::abs(p[a] - kRoomMin[a]), std::abs(p[a] - kRoomMax[a])});
  return d;
}

Pose cameraPose(const Sequence& seq, Timestamp t) {
  for (const GroundTruthState& s : seq.groundtruth)
    if (s.t == t) return s.T_WB * seq.camera->T_BS;
  ADD_FAILURE() << "no ground truth at image time " << t;
  return Pose();
}

TEST(FrontendSimDepthFilter, SeedsConvergeOntoTheRoomWalls) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("hdvio_frontend_sim_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  const std::string cmd = std::string(HDVIO_SIM_BINARY) + " --config " + HDVIO_SOURCE_DIR +
                          "/config/sim/ci_tiny.yaml --out " + out.string() + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const Sequence seq = io::readAsl(out.string());
  ASSERT_TRUE(seq.hasImages());
  ASSERT_GE(seq.images.size(), 18u);
  const CameraModel camera = CameraModel::fromCalibration(*seq.camera);

  auto makeFrame = [&](std::size_t i) {
    auto f = std::make_shared<Frame>();
    f->id = static_cast<int>(i);
    f->t = seq.images[i].t;
    f->pyramid = buildPyramid(io::loadImage(seq.images[i]), 4);
    f->T_cw = cameraPose(seq, f->t).inverse();
    return f;
  };
  const FramePtr kf = makeFrame(10);  // after the 1 s speed ramp
  DetectorOptions detector;
  detector.cell_size = 16;  // 320x240 images
  const FeatureGrid grid(camera.width(), camera.height(), detector.cell_size);
  std::vector<Feature> features;
  for (const Corner& c : detectCorners(kf->pyramid, detector, grid, std::vector<bool>(grid.cells(), false)))
    features.push_back({c.px, camera.unproject(c.px), c.level, -1});
  ASSERT_GT(features.size(), 60u);

  DepthFilter filter(camera, DepthFilterOptions());
  filter.addKeyframe(kf, features, 3.0, 0.5);
  std::vector<Seed> converged;
  for (std::size_t i = 11; i < 18; ++i)  // 0.7 s of flight at 2 m/s
    for (const Seed& s : filter.update(*makeFrame(i))) converged.push_back(s);
  std::filesystem::remove_all(out);

  EXPECT_GT(converged.size(), 0.4 * features.size()) << converged.size() << " of " << features.size();
  std::vector<double> rel;
  const Pose T_wc = kf->T_cw.inverse();
  for (const Seed& s : converged)
    rel.push_back(distanceToWalls(T_wc * (s.feature.f * s.depth())) / s.depth());
  ASSERT_FALSE(rel.empty());
  std::sort(rel.begin(), rel.end());
  EXPECT_LT(rel[rel.size() / 2], 0.02);       // median: within 2 % of the depth from a wall
  EXPECT_LT(rel[rel.size() * 9 / 10], 0.06);  // 90th percentile
}

}  // namespace
}  // namespace hdvio::frontend
