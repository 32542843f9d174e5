#include "hdvio/pipeline/frontend_handshake.h"

#include <algorithm>

#include "hdvio/factors/imu_preintegration.h"

namespace hdvio {

Pose predictPose(const NavState& s, const std::vector<ImuSample>& imu, Timestamp t,
                 const ImuNoiseParams& params) {
  if (t <= s.t) return s.T_WB;
  const PreintegratedImu pim = PreintegratedImu::integrate(imu, s.t, t, s.bias, params);
  const double dt = pim.dt();
  const Mat3 R = s.T_WB.R();
  return Pose(Mat3(R * pim.deltaR()), s.T_WB.p + s.v_W * dt + 0.5 * params.gravity * dt * dt +
                                          R * pim.deltaP());
}

frontend::BackendEstimate backendEstimate(const VioBackend& backend,
                                          const frontend::SemiDirectFrontend& fe) {
  frontend::BackendEstimate est;
  const std::vector<VioBackend::WindowPose> window = backend.windowPoses();
  for (const auto& kf : fe.map().keyframes) {
    const auto it = std::find_if(window.begin(), window.end(),
                                 [&](const VioBackend::WindowPose& s) { return s.t == kf->t; });
    if (it != window.end()) est.keyframe_T_WB[kf->id] = it->T_WB;
  }
  for (const auto& [id, lm] : fe.map().landmarks)
    if (const auto p = backend.landmarkPosition(id)) est.landmark_p_W[id] = *p;
  return est;
}

}  // namespace hdvio
