#include "hdvio/backend/imo/gate_reprojection.h"

namespace hdvio::imo {
namespace {
constexpr int kTheta = 0, kPos = 6;  // error-state offsets (imo_filter.h)
}  // namespace

bool projectGateCorner(const CameraModel& camera, const Pose& T_BC, const Mat3& R, const Vec3& p,
                       const Vec3& corner_W, Vec2* uv, Eigen::Matrix<double, 2, 6>* J) {
  const Mat3 R_CB = T_BC.R().transpose();
  const Vec3 p_B = R.transpose() * (corner_W - p);
  const Vec3 p_C = R_CB * (p_B - T_BC.p);
  Mat23 J_pi;
  if (!camera.project(p_C, uv, J ? &J_pi : nullptr)) return false;
  if (J) {
    // R Exp(d): p_B = Exp(-d) R^T (X - p) ~ p_B + [p_B]x d;  dp: p_B changes by -R^T dp.
    const Mat23 J_B = J_pi * R_CB;
    J->leftCols<3>() = J_B * hat(p_B);
    J->rightCols<3>() = -J_B * R.transpose();
  }
  return true;
}

GateFrameMeasurement gateFrameMeasurement(const CameraModel& camera, const Pose& T_BC,
                                          const ImoNominalState& x,
                                          const std::vector<GateCornerObservation>& observations,
                                          int state_dim) {
  GateFrameMeasurement m;
  std::vector<Vec2> residuals;
  std::vector<Eigen::Matrix<double, 2, 6>> jacobians;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    Vec2 uv;
    Eigen::Matrix<double, 2, 6> J;
    if (!projectGateCorner(camera, T_BC, x.R, x.p, observations[i].corner_W, &uv, &J)) continue;
    residuals.push_back(observations[i].uv - uv);
    jacobians.push_back(J);
    m.used.push_back(static_cast<int>(i));
  }
  const int rows = 2 * static_cast<int>(m.used.size());
  m.residual.resize(rows);
  m.H = MatX::Zero(rows, state_dim);
  for (std::size_t k = 0; k < m.used.size(); ++k) {
    const int r = 2 * static_cast<int>(k);
    m.residual.segment<2>(r) = residuals[k];
    m.H.block<2, 3>(r, kTheta) = jacobians[k].leftCols<3>();
    m.H.block<2, 3>(r, kPos) = jacobians[k].rightCols<3>();
  }
  return m;
}

}  // namespace hdvio::imo
