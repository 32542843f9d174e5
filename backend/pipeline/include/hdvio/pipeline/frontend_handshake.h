#pragma once
// The two directions of the frontend-backend handshake on images: the backend's latest state,
// carried forward with the IMU, seeds the frontend's sparse alignment (pose prior); after each
// backend step the optimized window keyframes and landmarks go back into the frontend's map
// (feedback), so the frontend's map stays metric. docs/visual_pipeline.md.
#include <vector>

#include "hdvio/backend/vio_backend.h"
#include "hdvio/frontend/semi_direct_frontend.h"

namespace hdvio {

// s carried forward to t with the IMU (what the frontend's sparse alignment starts from); s
// itself when t <= s.t. imu must cover [s.t, t].
Pose predictPose(const NavState& s, const std::vector<ImuSample>& imu, Timestamp t,
                 const ImuNoiseParams& params);

// Backend window poses at the frontend's keyframe times and the backend's landmarks.
frontend::BackendEstimate backendEstimate(const VioBackend& backend,
                                          const frontend::SemiDirectFrontend& fe);

}  // namespace hdvio
