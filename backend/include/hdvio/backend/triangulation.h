#pragma once
// Linear triangulation of one landmark from bearing rays of known camera poses.
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio {

struct TriangulationResult {
  Vec3 p_W = Vec3::Zero();
  double max_ray_angle_rad = 0.0;  // largest angle between any two rays (parallax)
  bool valid = false;              // in front of every camera and well conditioned
};

// T_WC: camera poses in the world; bearings_C: unit rays in each camera frame.
TriangulationResult triangulate(const std::vector<Pose>& T_WC, const std::vector<Vec3>& bearings_C);

}  // namespace hdvio
