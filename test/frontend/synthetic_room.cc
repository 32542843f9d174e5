#include "synthetic_room.h"

#include <cmath>
#include <limits>

namespace hdvio::frontend::test {
namespace {
constexpr double kHalf = 5.0, kHeight = 3.0;

unsigned hash(int x, int y, unsigned seed) {
  unsigned h = static_cast<unsigned>(x) * 374761393u + static_cast<unsigned>(y) * 668265263u + seed * 2246822519u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return h ^ (h >> 16);
}
}  // namespace

SyntheticRoom::SyntheticRoom(unsigned seed) : seed_(seed) {}

double SyntheticRoom::noise(double u, double v, int octave) const {
  const double fu = std::floor(u), fv = std::floor(v);
  const int x = static_cast<int>(fu), y = static_cast<int>(fv);
  double a = u - fu, b = v - fv;
  a = a * a * (3 - 2 * a);  // smoothstep keeps gradients continuous
  b = b * b * (3 - 2 * b);
  const unsigned s = seed_ + 101u * octave;
  auto val = [&](int i, int j) { return (hash(i, j, s) & 0xffff) / 65535.0; };
  return (1 - a) * (1 - b) * val(x, y) + a * (1 - b) * val(x + 1, y) + (1 - a) * b * val(x, y + 1) +
         a * b * val(x + 1, y + 1);
}

double SyntheticRoom::intensity(const Vec3& p) const {
  // Planar texture coordinates of the wall the point lies on.
  double u, v;
  if (std::abs(p.z()) < 1e-6 || std::abs(p.z() - kHeight) < 1e-6) { u = p.x(); v = p.y(); }
  else if (std::abs(std::abs(p.x()) - kHalf) < 1e-6) { u = p.y(); v = p.z(); }
  else { u = p.x(); v = p.z(); }
  double value = 0.0, amp = 1.0, freq = 2.5, norm = 0.0;
  for (int o = 0; o < 3; ++o) {
    value += amp * noise(u * freq, v * freq, o);
    norm += amp;
    amp *= 0.55;
    freq *= 2.1;
  }
  value /= norm;
  const double contrast = std::clamp((value - 0.5) * 3.5 + 0.5, 0.0, 1.0);
  return 25.0 + 205.0 * contrast;
}

double SyntheticRoom::castRay(const Vec3& o, const Vec3& d, Vec3* hit) const {
  double best = std::numeric_limits<double>::infinity();
  auto test = [&](int axis, double plane) {
    if (std::abs(d[axis]) < 1e-12) return;
    const double t = (plane - o[axis]) / d[axis];
    if (t > 1e-9 && t < best) best = t;
  };
  test(0, -kHalf); test(0, kHalf); test(1, -kHalf); test(1, kHalf); test(2, 0.0); test(2, kHeight);
  *hit = o + best * d;
  return best;
}

cv::Mat SyntheticRoom::render(const CameraModel& camera, const Pose& T_wc) const {
  cv::Mat img(camera.height(), camera.width(), CV_8UC1);
  const Mat3 R = T_wc.R();
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      Vec3 hit;
      castRay(T_wc.p, R * camera.unproject(Vec2(x, y)), &hit);
      img.at<unsigned char>(y, x) = static_cast<unsigned char>(std::lround(intensity(hit)));
    }
  }
  return img;
}

double SyntheticRoom::depthAt(const CameraModel& camera, const Pose& T_wc, const Vec2& px) const {
  const Vec3 f = camera.unproject(px);
  Vec3 hit;
  const double range = castRay(T_wc.p, T_wc.R() * f, &hit);
  return range * f.z();
}

CameraCalibration syntheticCalibration() {
  CameraCalibration c;
  c.width = 752;
  c.height = 480;
  c.rate_hz = 20.0;
  c.fu = 458.0;
  c.fv = 457.0;
  c.cu = 367.0;
  c.cv = 248.0;
  c.distortion = DistortionModel::kRadialTangential;
  c.distortion_coefficients = {-0.1, 0.02, 0.0002, 0.00002};
  return c;
}

Pose lookingForward(const Vec3& position, double yaw, double pitch) {
  Mat3 R_forward;  // camera z along world x, camera x along -y, camera y along -z
  R_forward << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Mat3 R = so3Exp(Vec3(0, 0, yaw)) * so3Exp(Vec3(0, pitch, 0)) * R_forward;
  return Pose(R, position);
}

}  // namespace hdvio::frontend::test
