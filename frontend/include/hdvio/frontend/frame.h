#pragma once
// The frontend's map: frames with their pyramids and features, and 3-D landmarks that
// remember in which keyframes they were observed. Poses are T_CW (world -> camera), the form
// every projection uses; the public API converts to T_WB.
#include <map>
#include <memory>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/pyramid.h"

namespace hdvio::frontend {

struct Feature {
  Vec2 px;                // level-0 distorted pixel
  Vec3 f;                 // unit bearing in the camera frame
  int level = 0;          // pyramid level of its precision: detected on, or the finest alignment reached
  int landmark_id = -1;   // -1: not (yet) a landmark
};

struct Frame {
  int id = 0;
  Timestamp t = 0;
  Pyramid pyramid;
  Pose T_cw;
  std::vector<Feature> features;
  bool is_keyframe = false;

  Vec3 cameraCenter() const { return T_cw.inverse().p; }
};
using FramePtr = std::shared_ptr<Frame>;

struct Landmark {
  struct Observation {
    FramePtr keyframe;
    int feature = 0;  // index into keyframe->features
  };
  int id = 0;
  Vec3 p_w = Vec3::Zero();
  // False while the depth still comes from a depth-filter seed (only at initialization).
  bool converged = true;
  std::vector<Observation> observations;
  int failed_alignments = 0;
};
using LandmarkPtr = std::shared_ptr<Landmark>;

// Keyframes and landmarks the frontend tracks against.
struct Map {
  std::vector<FramePtr> keyframes;  // oldest first
  std::map<int, LandmarkPtr> landmarks;
  int next_landmark_id = 0;

  // id: one reserved earlier with next_landmark_id++ (a seed's track), or -1 for a new one.
  LandmarkPtr addLandmark(const Vec3& p_w, bool converged, int id = -1) {
    auto lm = std::make_shared<Landmark>();
    lm->id = id >= 0 ? id : next_landmark_id++;
    lm->p_w = p_w;
    lm->converged = converged;
    landmarks[lm->id] = lm;
    return lm;
  }
  // Removes the keyframe, its observations and landmarks left without any.
  void removeKeyframe(const FramePtr& kf);
  void removeLandmark(int id);
  void clear() {
    keyframes.clear();
    landmarks.clear();
  }
};

}  // namespace hdvio::frontend
