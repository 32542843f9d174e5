#include <algorithm>

#include "hdvio/frontend/frame.h"

namespace hdvio::frontend {

void Map::removeKeyframe(const FramePtr& kf) {
  keyframes.erase(std::remove(keyframes.begin(), keyframes.end(), kf), keyframes.end());
  for (Feature& ftr : kf->features) {
    if (ftr.landmark_id < 0) continue;
    auto it = landmarks.find(ftr.landmark_id);
    if (it == landmarks.end()) continue;
    auto& obs = it->second->observations;
    obs.erase(std::remove_if(obs.begin(), obs.end(),
                             [&](const Landmark::Observation& o) { return o.keyframe == kf; }),
              obs.end());
    if (obs.empty()) landmarks.erase(it);
  }
}

void Map::removeLandmark(int id) {
  auto it = landmarks.find(id);
  if (it == landmarks.end()) return;
  for (auto& o : it->second->observations) o.keyframe->features[o.feature].landmark_id = -1;
  landmarks.erase(it);
}

}  // namespace hdvio::frontend
