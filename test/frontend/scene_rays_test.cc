// hdvio_feature_truth's corner classifier (apps/frontend_demo/scene_rays.h): a corner on a gate's
// outer edge, with the far wall behind it, is an occlusion boundary; one in the middle of a wall
// is a surface point; one next to the edge between two walls is a crease. The ring of rays
// scales with the pyramid level, so a corner 6 px from the gate's edge is a surface point on
// level 0 (rays up to 4 px) and an occlusion on level 1 (up to 8 px).
#include "scene_rays.h"

#include <gtest/gtest.h>

namespace hdvio {
namespace {

class CornerClassTest : public ::testing::Test {
 protected:
  CornerClassTest()
      : scene_(roomConfig(), {sim::GateConfig{Vec3(2.0, 0.0, 1.5), 0.0}}, 1),
        camera_(320, 240, 200.0, 200.0, 160.0, 120.0, DistortionModel::kRadialTangential,
                {0.0, 0.0, 0.0, 0.0}) {
    // At (0, 0, 1.5) looking along world x (camera z = x, camera x = -y, camera y = -z).
    Mat3 R_WC;
    R_WC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    T_WC_ = Pose(Quat(R_WC), Vec3(0.0, 0.0, 1.5));
  }
  static sim::SceneConfig roomConfig() {
    sim::SceneConfig c;
    c.room_min = Vec3(-4.0, -3.0, 0.0);
    c.room_max = Vec3(4.0, 3.0, 3.0);
    c.texel_size = 0.1;
    c.render_gates = true;
    c.gate_inner_size = 1.5;  // outer edge at 0.95 m from the gate's centre
    c.gate_border = 0.2;
    return c;
  }
  Vec2 pixelOf(const Vec3& p_W) const {
    Vec2 uv;
    EXPECT_TRUE(camera_.project(T_WC_.inverse() * p_W, &uv));
    return uv;
  }
  CornerKind kind(const Vec3& p_W, int level) const {
    return classifyCorner(scene_, camera_, T_WC_, pixelOf(p_W), level).kind;
  }

  sim::Scene scene_;
  CameraModel camera_;
  Pose T_WC_;
};

TEST_F(CornerClassTest, RaysNameTheSurfaceTheyMeet) {
  const RayHit wall = castRayHit(scene_, T_WC_.p, Vec3(1.0, -0.6, -0.2).normalized());
  EXPECT_EQ(wall.surface, 1);  // the x = room_max face
  EXPECT_FALSE(wall.onGate());
  const RayHit gate = castRayHit(scene_, T_WC_.p, Vec3(1.0, 0.0, 0.425).normalized());  // top bar
  EXPECT_EQ(gate.surface, kGateSurface);
  EXPECT_NEAR(gate.distance, 1.95 * Vec3(1.0, 0.0, 0.425).norm(), 1e-9);  // front face, x = 1.95
}

TEST_F(CornerClassTest, GateEdgeOverTheFarWallIsAnOcclusion) {
  // The top outer edge of the gate frame (z = 1.5 + 0.95, front face x = 1.95).
  EXPECT_EQ(kind(Vec3(1.95, 0.3, 2.45), 0), CornerKind::kOcclusion);
  EXPECT_EQ(kind(Vec3(1.95, 0.3, 2.45), 2), CornerKind::kOcclusion);
}

TEST_F(CornerClassTest, MiddleOfAWallIsASurfacePoint) {
  EXPECT_EQ(kind(Vec3(4.0, -2.5, 0.7), 0), CornerKind::kSurface);
  EXPECT_EQ(kind(Vec3(4.0, -2.5, 0.7), 2), CornerKind::kSurface);
  const CornerClass c = classifyCorner(scene_, camera_, T_WC_, pixelOf(Vec3(4.0, -2.5, 0.7)), 1);
  EXPECT_EQ(c.centre.surface, 1);
  EXPECT_NEAR(c.centre.distance, Vec3(4.0, -2.5, -0.8).norm(), 1e-9);
  EXPECT_LT(c.max_relative_depth_step, 0.15);
}

TEST_F(CornerClassTest, NextToTheEdgeOfTwoWallsIsACrease) {
  EXPECT_EQ(kind(Vec3(4.0, -2.98, 1.2), 0), CornerKind::kCrease);
}

TEST_F(CornerClassTest, RingScalesWithThePyramidLevel) {
  // 6 px (level 0) above the gate's top edge at 2 m: 0.06 m at 200 px per unit depth.
  const Vec2 edge = pixelOf(Vec3(1.95, 0.3, 2.45));
  const Vec2 px = edge + Vec2(0.0, -6.0);
  EXPECT_EQ(classifyCorner(scene_, camera_, T_WC_, px, 0).kind, CornerKind::kSurface);
  EXPECT_EQ(classifyCorner(scene_, camera_, T_WC_, px, 1).kind, CornerKind::kOcclusion);
}

}  // namespace
}  // namespace hdvio
