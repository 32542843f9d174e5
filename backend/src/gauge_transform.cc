#include "hdvio/backend/gauge_transform.h"

#include <cmath>

namespace hdvio {

GaugeTransform GaugeTransform::restoring(const Pose& reference, const Pose& moved) {
  // argmax_psi trace(R_reference^T Rz(psi) R_moved) = trace(Rz(psi) M) with
  // M = R_moved R_reference^T, which is cos(psi) (M00 + M11) + sin(psi) (M01 - M10) + M22.
  const Mat3 M = moved.R() * reference.R().transpose();
  const double psi = std::atan2(M(0, 1) - M(1, 0), M(0, 0) + M(1, 1));
  GaugeTransform g;
  g.R = Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix();
  g.from = moved.p;
  g.to = reference.p;
  return g;
}

void GaugeTransform::apply(Values* values) const {
  for (const Key k : values->keys()) {
    switch (k.letter()) {
      case 'x':
        values->updatePose(k, pose(values->pose(k)));
        break;
      case 'l':
        values->update(k, point(values->vec3(k)));
        break;
      case 'v':
      case 'f':
        values->update(k, R * values->vec3(k));
        break;
      default:
        break;
    }
  }
}

}  // namespace hdvio
