#pragma once
// The world the camera sees: an axis-aligned box room (hall) whose six faces carry
// deterministic multi-scale procedural textures (value noise + blobs + checker patches, with
// a mip pyramid for alias-free minification), optional racing gates (thin square frames),
// and ground-truth landmarks on the faces.
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/core/lie.h"
#include "hdvio/sim/sim_config.h"

namespace hdvio::sim {

// Face index = 2 * normal_axis + (0 at room_min, 1 at room_max). A face's texture columns
// run along axis (a+1)%3 and rows along (a+2)%3; texel (i, j) sits at room_min + (i, j) * texel.
constexpr int kNumFaces = 6;

struct Gate {
  Vec3 center = Vec3::Zero();
  Mat3 R_WG = Mat3::Identity();  // gate x = flight direction, z = up
  double inner_half = 0.75, outer_half = 0.95, half_depth = 0.05;
};

class Scene {
 public:
  Scene(const SceneConfig& config, const std::vector<GateConfig>& gates, std::uint64_t seed);
  // For tests: given level-0 textures (CV_32F, gray levels), sizes must match faceSize().
  Scene(const Vec3& room_min, const Vec3& room_max, double texel,
        const std::array<cv::Mat, kNumFaces>& textures, std::vector<Gate> gates = {});

  static cv::Size faceSize(const Vec3& room_min, const Vec3& room_max, double texel, int face);

  const Vec3& roomMin() const { return min_; }
  const Vec3& roomMax() const { return max_; }
  double texel() const { return texel_; }
  const std::vector<cv::Mat>& mipLevels(int face) const { return mips_[face]; }
  const std::vector<Gate>& gates() const { return gates_; }

  // Uniform random points on the faces (by area), deterministic for a seed.
  std::vector<Vec3> sampleSurfacePoints(int count, std::uint64_t seed) const;
  // Whether a gate blocks the straight segment from a to b.
  bool segmentBlocked(const Vec3& a, const Vec3& b) const;
  // First gate hit along o + t d (t in (0, t_max)); returns t or -1, and a gray level.
  double intersectGates(const Vec3& o, const Vec3& d, double t_max, float* intensity) const;
  // The same for one gate, with the ray already in gate coordinates (renderers precompute).
  static double intersectGate(const Gate& gate, const Vec3& o_G, const Vec3& d_G, double t_max,
                              float* intensity);

 private:
  void buildMips(int face, const cv::Mat& level0);

  Vec3 min_, max_;
  double texel_;
  std::array<std::vector<cv::Mat>, kNumFaces> mips_;
  std::vector<Gate> gates_;
};

}  // namespace hdvio::sim
