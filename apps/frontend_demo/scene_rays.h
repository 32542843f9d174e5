#pragma once
// Rays against the simulator's scene for hdvio_feature_truth: which surface a pixel's ray meets
// and whether the neighbourhood of a corner is one surface (a 3-D point) or straddles a depth
// discontinuity (an occlusion boundary: a gate's edge over the far wall, a T-junction whose
// image position slides with parallax).
#include "hdvio/core/camera_model.h"
#include "hdvio/core/lie.h"
#include "hdvio/sim/scene.h"

namespace hdvio {

// Surface ids: 0..5 the room's faces (sim::kNumFaces convention), kGateSurface + i gate i.
constexpr int kGateSurface = sim::kNumFaces;

struct RayHit {
  double distance = -1.0;  // along the unit direction; negative: no hit (origin outside the room)
  int surface = -1;
  bool valid() const { return distance > 0.0; }
  bool onGate() const { return surface >= kGateSurface; }
};

// First scene surface along the unit direction d from o (inside the room): room box or gate.
RayHit castRayHit(const sim::Scene& scene, const Vec3& o, const Vec3& d);
// Distance only; negative when o is outside the room.
double castRay(const sim::Scene& scene, const Vec3& o, const Vec3& d);

enum class CornerKind {
  kSurface,    // every ray of the neighbourhood meets the surface of the centre at a similar depth
  kCrease,     // two room faces meet in the neighbourhood (a real 3-D edge, depth continuous)
  kSlanted,    // no occlusion, but the depth changes by more than the step threshold across the
               // neighbourhood (a surface seen at a grazing angle): a 3-D point, strongly warped
  kOcclusion,  // a gate's edge against a wall or another gate: no single 3-D point
  kUnknown,    // the centre ray met nothing
};
const char* cornerKindName(CornerKind k);
constexpr int kNumCornerKinds = 5;

struct CornerClassOptions {
  // Rays on rings of these radii around the corner, in pixels of its pyramid level (x 2^level
  // at level 0), 8 directions each: 2 and 4 cover the 8x8 patch that feature alignment matches.
  double radii_level_px[2] = {2.0, 4.0};
  // |d - d_centre| / min(d, d_centre) above this: a depth step. Only a gate occludes in the
  // simulated scene, so a step without a gate is a slanted surface, one with a gate (the gate's
  // inner side seen across its 10 cm depth included) an occlusion.
  double max_relative_depth_step = 0.15;
};

struct CornerClass {
  CornerKind kind = CornerKind::kUnknown;
  RayHit centre;
  double max_relative_depth_step = 0.0;  // over the neighbourhood's rays
};

// px: distorted level-0 pixel seen by the camera at T_WC (true pose).
CornerClass classifyCorner(const sim::Scene& scene, const CameraModel& camera, const Pose& T_WC,
                           const Vec2& px, int level, const CornerClassOptions& options = {});

}  // namespace hdvio
