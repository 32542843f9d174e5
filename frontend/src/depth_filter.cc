#include "hdvio/frontend/depth_filter.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "hdvio/frontend/patch_alignment.h"

namespace hdvio::frontend {

void updateSeed(double x, double tau2, Seed* s) {
  const double norm_scale = std::sqrt(s->sigma2 + tau2);
  if (!std::isfinite(norm_scale) || norm_scale <= 0.0) return;
  const double s2 = 1.0 / (1.0 / s->sigma2 + 1.0 / tau2);
  const double m = s2 * (s->mu / s->sigma2 + x / tau2);
  const double z = (x - s->mu) / norm_scale;
  const double pdf = std::exp(-0.5 * z * z) / (norm_scale * std::sqrt(2.0 * M_PI));
  double c1 = s->a / (s->a + s->b) * pdf;
  double c2 = s->b / (s->a + s->b) / s->z_range;
  const double normalization = c1 + c2;
  if (!(normalization > 0.0)) return;
  c1 /= normalization;
  c2 /= normalization;
  const double ab = s->a + s->b;
  const double f = c1 * (s->a + 1.0) / (ab + 1.0) + c2 * s->a / (ab + 1.0);
  const double e = c1 * (s->a + 1.0) * (s->a + 2.0) / ((ab + 1.0) * (ab + 2.0)) +
                   c2 * s->a * (s->a + 1.0) / ((ab + 1.0) * (ab + 2.0));
  const double mu_new = c1 * m + c2 * s->mu;
  s->sigma2 = c1 * (s2 + m * m) + c2 * (s->sigma2 + s->mu * s->mu) - mu_new * mu_new;
  s->mu = mu_new;
  s->a = (e - f) / (f - e / f);
  s->b = s->a * (1.0 - f) / f;
}

double computeTau(const Pose& T_ref_cur, const Vec3& f, double z, double px_error_angle) {
  const Vec3 t = T_ref_cur.p;
  const Vec3 a = f * z - t;
  const double t_norm = t.norm(), a_norm = a.norm();
  const double alpha = std::acos(std::clamp(f.dot(t) / t_norm, -1.0, 1.0));
  const double beta = std::acos(std::clamp(a.dot(-t) / (t_norm * a_norm), -1.0, 1.0));
  const double beta_plus = beta + px_error_angle;
  const double gamma_plus = M_PI - alpha - beta_plus;
  const double z_plus = t_norm * std::sin(beta_plus) / std::sin(gamma_plus);
  return z_plus - z;
}

std::vector<int> DepthFilter::addKeyframe(const FramePtr& keyframe,
                                          const std::vector<Feature>& features,
                                          double depth_mean, double depth_min) {
  for (Seed& s : seeds_) ++s.keyframe_age;
  seeds_.erase(std::remove_if(seeds_.begin(), seeds_.end(),
                              [&](const Seed& s) {
                                return s.keyframe_age > options_.max_keyframe_age &&
                                       s.landmark_id < 0;
                              }),
               seeds_.end());
  std::vector<int> ids;
  for (const Feature& ftr : features) {
    Seed s;
    s.id = next_seed_id_++;
    s.keyframe = keyframe;
    s.feature = ftr;
    s.mu = 1.0 / depth_mean;
    s.z_range = 1.0 / depth_min;
    s.sigma2 = s.z_range * s.z_range / 36.0;
    seeds_.push_back(s);
    ids.push_back(s.id);
  }
  return ids;
}

void DepthFilter::attachLandmark(int seed_id, int landmark_id) {
  for (Seed& s : seeds_)
    if (s.id == seed_id) s.landmark_id = landmark_id;
}

void DepthFilter::setTrackId(int seed_id, int track_id) {
  for (Seed& s : seeds_)
    if (s.id == seed_id) s.track_id = track_id;
}

void DepthFilter::removeSeedsOf(const FramePtr& keyframe) {
  seeds_.erase(std::remove_if(seeds_.begin(), seeds_.end(),
                              [&](const Seed& s) { return s.keyframe == keyframe; }),
               seeds_.end());
}

bool DepthFilter::findEpipolarMatch(const Seed& seed, const Frame& frame, const Pose& T_cur_ref,
                                    Vec2* px_found, int* level_found) const {
  const Vec3& f_ref = seed.feature.f;
  const double sigma = std::sqrt(seed.sigma2);
  const double d_est = 1.0 / seed.mu;
  const double d_min = 1.0 / (seed.mu + sigma);
  const double d_max = 1.0 / std::max(seed.mu - sigma, 1e-7);
  const Vec3 p_min = T_cur_ref * (f_ref * d_min), p_max = T_cur_ref * (f_ref * d_max);
  if (p_min.z() < 1e-6 || (T_cur_ref * (f_ref * d_est)).z() < 1e-6) return false;
  // Epipolar segment in the normalized plane; the far end is clipped in front of the camera.
  const Vec2 a = p_min.head<2>() / p_min.z();
  const Vec2 b = p_max.z() > 1e-6 ? Vec2(p_max.head<2>() / p_max.z()) : a;

  const Eigen::Matrix2d A = affineWarp(camera_, seed.feature.px, f_ref, d_est,
                                       seed.feature.level, T_cur_ref);
  const int level = bestSearchLevel(A, std::min<int>(options_.max_pyramid_level,
                                                      static_cast<int>(frame.pyramid.size()) - 1));
  BorderedPatch patch;
  if (!warpPatch(A, seed.keyframe->pyramid[seed.feature.level], seed.feature.px,
                 seed.feature.level, level, &patch))
    return false;
  const double scale = 1.0 / (1 << level);
  const cv::Mat& img = frame.pyramid[level];
  const double epi_px = (b - a).norm() * camera_.focalLength() * scale;

  Vec2 best_px;
  if (epi_px < 2.0) {
    Vec2 px;
    if (!camera_.project(T_cur_ref * (f_ref * d_est), &px)) return false;
    best_px = px * scale;
  } else {
    const int steps = static_cast<int>(epi_px / 0.7);
    if (steps > options_.max_search_steps) return false;
    double best = std::numeric_limits<double>::infinity();
    const int border = kAlignHalf + 2;
    Eigen::Vector2i last(-1, -1);
    for (int i = 0; i <= steps; ++i) {
      const Vec2 uv = a + (b - a) * (static_cast<double>(i) / steps);
      Vec2 px;
      if (!camera_.project(Vec3(uv.x(), uv.y(), 1.0), &px)) continue;
      const Eigen::Vector2i q((px * scale).array().round().cast<int>());
      if (q == last) continue;
      last = q;
      if (q.x() < border || q.y() < border || q.x() >= img.cols - border || q.y() >= img.rows - border)
        continue;
      const double score = zmssd(img, patch, q.x(), q.y());
      if (score < best) {
        best = score;
        best_px = q.cast<double>();
      }
    }
    if (best > options_.max_zmssd_per_pixel * kAlignPatch * kAlignPatch) return false;
  }
  if (!align2D(img, patch, 10, &best_px)) return false;
  // The match's precision is the finest level it reaches (as the reprojector's features).
  const int finest = refineToFinerLevels(frame.pyramid, A, seed.keyframe->pyramid, seed.feature.px,
                                         seed.feature.level, level, &best_px);
  *px_found = best_px * static_cast<double>(1 << finest);
  *level_found = finest;
  return true;
}

std::vector<Seed> DepthFilter::update(const Frame& frame, std::vector<Match>* matches) {
  std::vector<Seed> converged;
  const double px_error_angle = 2.0 * std::atan(options_.pixel_noise / (2.0 * camera_.focalLength()));
  for (auto it = seeds_.begin(); it != seeds_.end();) {
    Seed& s = *it;
    const Pose T_cur_ref = frame.T_cw * s.keyframe->T_cw.inverse();
    const Pose T_ref_cur = T_cur_ref.inverse();
    // Without parallax a match says nothing about depth.
    if (T_ref_cur.p.norm() < options_.min_parallax_ratio * s.depth()) {
      ++it;
      continue;
    }
    Vec2 px_cur;
    Vec2 px_check;
    if (!camera_.project(T_cur_ref * (s.feature.f * s.depth()), &px_check) ||
        !camera_.inImage(px_check, 8.0)) {
      ++it;
      continue;
    }
    int level = 0;
    if (!findEpipolarMatch(s, frame, T_cur_ref, &px_cur, &level)) {
      s.b += 1.0;  // a failed match is evidence for an outlier seed
      ++it;
      continue;
    }
    // Triangulate: d_ref R f_ref - d_cur f_cur = -t, solved in least squares.
    const Vec3 f_cur = camera_.unproject(px_cur);
    Eigen::Matrix<double, 3, 2> M;
    M.col(0) = T_cur_ref.q * s.feature.f;
    M.col(1) = f_cur;
    const Eigen::Vector2d d = -(M.transpose() * M).ldlt().solve(M.transpose() * T_cur_ref.p);
    const double z = std::abs(d.x());
    if (!std::isfinite(z) || z < 1e-3) {
      ++it;
      continue;
    }
    const double tau = computeTau(T_ref_cur, s.feature.f, z, px_error_angle);
    const double tau_inverse = 0.5 * (1.0 / std::max(1e-7, z - tau) - 1.0 / (z + tau));
    if (matches && s.track_id >= 0) matches->push_back({s.track_id, px_cur, level, s.updates});
    updateSeed(1.0 / z, tau_inverse * tau_inverse, &s);
    s.measured_depth = z;
    ++s.updates;
    if (!std::isfinite(s.mu) || !std::isfinite(s.sigma2) || s.mu <= 0.0) {
      it = seeds_.erase(it);
      continue;
    }
    const bool precise = s.converged(options_.convergence_ratio) ||
                         (s.updates >= options_.min_updates_relative &&
                          std::sqrt(s.sigma2) < options_.relative_sigma * s.mu);
    if (precise && s.a / (s.a + s.b) > 0.5) {
      converged.push_back(s);
      it = seeds_.erase(it);
      continue;
    }
    ++it;
  }
  return converged;
}

}  // namespace hdvio::frontend
