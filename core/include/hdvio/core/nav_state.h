#pragma once
#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio {

// The estimated state of the vehicle at one time.
struct NavState {
  Timestamp t = 0;
  Pose T_WB;
  Vec3 v_W = Vec3::Zero();
  Vec6 bias = Vec6::Zero();         // [bg, ba]
  Vec3 f_ext_W = Vec3::Zero();      // mass-normalized external force, world frame
};

}  // namespace hdvio
