#include "feature_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "hdvio/core/error.h"

namespace hdvio {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

std::string statsLine(const ErrorStats& s) {
  char b[256];
  std::snprintf(b, sizeof(b), "n %7d  rms %6.3f  median %6.3f  p90 %6.3f  >1px %5.1f%%  >2px %5.1f%%  "
                ">5px %5.2f%%  rms(<5px) %6.3f", s.count, s.rms, s.median, s.p90,
                100 * s.frac_above_1px, 100 * s.frac_above_2px, 100 * s.frac_above_5px, s.rms_below_5px);
  return b;
}

ErrorStats errorStats(std::vector<double> e) {
  ErrorStats s;
  s.count = static_cast<int>(e.size());
  if (e.empty()) return s;
  double sum2 = 0, sum2_in = 0;
  int n1 = 0, n2 = 0, n5 = 0;
  for (double x : e) {
    sum2 += x * x;
    n1 += x > 1.0;
    n2 += x > 2.0;
    if (x > 5.0) ++n5;
    else sum2_in += x * x;
  }
  const double n = static_cast<double>(e.size());
  s.rms = std::sqrt(sum2 / n);
  s.rms_below_5px = n5 < s.count ? std::sqrt(sum2_in / (n - n5)) : 0.0;
  s.frac_above_1px = n1 / n;
  s.frac_above_2px = n2 / n;
  s.frac_above_5px = n5 / n;
  s.median = quantile(e, 0.5);
  s.p90 = quantile(e, 0.9);
  return s;
}

FeatureTruthChecker::FeatureTruthChecker(const sim::Scene& scene, CameraModel camera,
                                         const Pose& T_BS, TruthPose truth,
                                         CornerClassOptions corner_options)
    : scene_(scene), camera_(std::move(camera)), T_BS_(T_BS), truth_(std::move(truth)),
      corner_options_(corner_options) {}

void PipelineCounts::add(const ImageStep& step) {
  ++images_;
  if (!step.record.tracked) return;
  ++tracked_;
  keyframes_ += step.record.frontend_keyframe;
  observations_ += static_cast<long long>(step.observations.size());
  if (step.result && step.record.used_by_backend) {
    ++backend_frames_;
    backend_obs_ += step.result->observations_used;
    backend_landmarks_ += step.result->landmarks_in_window;
    backend_outliers_ += step.result->outliers_removed;
  }
}

void PipelineCounts::fill(FeatureTruthSummary* s) const {
  s->images = images_;
  s->tracked_images = tracked_;
  s->backend_images = backend_frames_;
  s->keyframes = keyframes_;
  s->observations_per_image = tracked_ ? static_cast<double>(observations_) / tracked_ : 0.0;
  if (backend_frames_ > 0) {
    s->backend_observations = backend_obs_ / backend_frames_;
    s->backend_landmarks = backend_landmarks_ / backend_frames_;
    s->backend_outliers_per_image = backend_outliers_ / backend_frames_;
  }
}

void fillErrorBreakdown(const std::vector<ScoredObservation>& scored, const std::vector<double>& track_lengths,
                        FeatureTruthSummary* s) {
  std::vector<double> all;
  std::map<int, std::vector<double>> level;
  const std::vector<std::pair<std::string, int>> ages = {
      {"1-2", 2}, {"3-5", 5}, {"6-10", 10}, {"11-20", 20}, {"21-40", 40}, {">40", 1 << 30}};
  std::vector<std::vector<double>> age(ages.size());
  for (const ScoredObservation& o : scored) {
    all.push_back(o.error_px);
    level[o.level].push_back(o.error_px);
    for (size_t k = 0; k < ages.size(); ++k)
      if (o.age <= ages[k].second) {
        age[k].push_back(o.error_px);
        break;
      }
  }
  s->all = errorStats(all);
  for (auto& [l, v] : level) s->by_level[l] = errorStats(v);
  for (size_t k = 0; k < ages.size(); ++k) s->by_age.push_back({ages[k].first, errorStats(age[k])});
  s->landmarks = static_cast<int>(track_lengths.size());
  if (!track_lengths.empty()) {
    double sum = 0;
    for (double l : track_lengths) sum += l;
    s->track_mean = sum / static_cast<double>(track_lengths.size());
  }
  s->track_median = quantile(track_lengths, 0.5);
  s->track_p90 = quantile(track_lengths, 0.9);
}

void FeatureTruthChecker::add(const ImageStep& step) {
  const int image = counts_.images();
  counts_.add(step);
  if (image == 0) first_t_ = step.record.t;
  if (!step.record.tracked) return;
  const Timestamp t = step.record.t;
  const Pose T_WC = trueCamera(t);
  const Pose T_CW = T_WC.inverse();
  for (const auto& o : step.observations) {
    auto [it, fresh] = tracks_.try_emplace(o.landmark_id);
    Track& tr = it->second;
    ++tr.count;
    if (fresh) {
      tr.first_image = image;
      tr.first_level = o.level;
      tr.first_px = o.px;
      tr.corner = classifyCorner(scene_, camera_, T_WC, o.px, o.level, corner_options_);
      tr.valid = tr.corner.centre.valid();
      if (tr.valid) {
        const Vec3 d = T_WC.q * camera_.unproject(o.px).normalized();
        tr.p_W = T_WC.p + tr.corner.centre.distance * d;
      }
      continue;
    }
    if (!tr.valid) continue;
    Vec2 uv;
    if (!camera_.project(T_CW * tr.p_W, &uv)) continue;
    checked_.push_back({t, o.landmark_id, o.level, image - tr.first_image, o.px - uv, o.px});
  }
  for (const auto& l : step.new_landmarks) {
    ++new_landmarks_;
    if (!l.converged) {
      ++new_unconverged_;
      continue;
    }
    // Depth from this image's true camera along the landmark's direction: the frontend's world
    // is the backend's, which started at the true state, so this includes the pose error.
    const Vec3 d = (l.p_W - T_WC.p).normalized();
    const double d_true = castRay(scene_, T_WC.p, d);
    if (d_true > 0.0) new_depth_errors_.push_back(std::abs((l.p_W - T_WC.p).norm() - d_true) / d_true);
  }
}

FeatureTruthSummary FeatureTruthChecker::summary() const {
  FeatureTruthSummary s;
  counts_.fill(&s);
  std::vector<ScoredObservation> scored;
  for (const Checked& c : checked_) scored.push_back({c.err.norm(), c.level, c.age});
  std::vector<double> lengths;
  for (const auto& [id, tr] : tracks_) lengths.push_back(tr.count);
  fillErrorBreakdown(scored, lengths, &s);
  const std::vector<std::pair<std::string, double>> spans = {
      {"0-1.5", 1.5}, {"1.5-3", 3}, {"3-5", 5}, {"5-8", 8}, {"8-20", 20}, {">20", 1e300}};
  std::array<std::vector<double>, kNumCornerKinds> corner;
  std::vector<std::array<std::vector<double>, kNumCornerKinds>> span_corner(spans.size());
  for (const Checked& c : checked_) {
    const int k = static_cast<int>(tracks_.at(c.id).corner.kind);
    const double e = c.err.norm();
    corner[k].push_back(e);
    const double t = toSeconds(c.t - first_t_);
    for (size_t j = 0; j < spans.size(); ++j)
      if (t < spans[j].second) {
        span_corner[j][k].push_back(e);
        break;
      }
  }
  for (int k = 0; k < kNumCornerKinds; ++k) s.by_corner[k] = errorStats(corner[k]);
  for (size_t j = 0; j < spans.size(); ++j) {
    FeatureTruthSummary::SpanRow row{spans[j].first, {}};
    for (int k = 0; k < kNumCornerKinds; ++k) row.by_corner[k] = errorStats(span_corner[j][k]);
    s.by_span.push_back(row);
  }
  for (const auto& [id, tr] : tracks_) ++s.landmarks_by_corner[static_cast<int>(tr.corner.kind)];
  s.new_landmarks_per_keyframe = s.keyframes ? static_cast<double>(new_landmarks_) / s.keyframes : 0.0;
  s.new_unconverged_fraction = new_landmarks_ ? static_cast<double>(new_unconverged_) / new_landmarks_ : 0.0;
  s.new_depth_error_median = quantile(new_depth_errors_, 0.5);
  s.new_depth_error_p90 = quantile(new_depth_errors_, 0.9);
  return s;
}

void FeatureTruthChecker::writeObservations(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "cannot write observations");
  out << "# t[ns],landmark,level,age[images],err_u[px],err_v[px],u[px],v[px],first_class,"
         "first_surface,first_distance[m],first_level,first_u[px],first_v[px],first_depth_step\n";
  char line[320];
  for (const Checked& c : checked_) {
    const Track& tr = tracks_.at(c.id);
    std::snprintf(line, sizeof(line), "%lld,%d,%d,%d,%.4f,%.4f,%.2f,%.2f,%s,%d,%.3f,%d,%.2f,%.2f,%.3f\n",
                  static_cast<long long>(c.t), c.id, c.level, c.age, c.err.x(), c.err.y(), c.px.x(),
                  c.px.y(), cornerKindName(tr.corner.kind), tr.corner.centre.surface,
                  tr.corner.centre.distance, tr.first_level, tr.first_px.x(), tr.first_px.y(),
                  tr.corner.max_relative_depth_step);
    out << line;
  }
  if (!out) throw InputError(path, 0, "cannot write observations");
}

std::string formatErrorSummary(const FeatureTruthSummary& s, const ImageRunOutput& run,
                               const std::string& what, int scored_landmarks) {
  std::string o;
  char b[512];
  std::snprintf(b, sizeof(b), "images %d, tracked %d, given to the backend %d, lost %d, re-initializations %d, "
                "frontend keyframes %d\n", s.images, s.tracked_images, s.backend_images,
                run.lost_images, run.reinitializations, s.keyframes);
  o += b;
  const std::string scored =
      scored_landmarks >= 0 ? " (" + std::to_string(scored_landmarks) + " in 3+ images)" : std::string();
  std::snprintf(b, sizeof(b), "frontend observations per tracked image %.1f; landmarks %d%s, images per "
                "track mean %.1f median %.0f p90 %.0f\n", s.observations_per_image, s.landmarks,
                scored.c_str(), s.track_mean, s.track_median, s.track_p90);
  o += b;
  o += what + " [px], all: " + statsLine(s.all) + "\n";
  for (const auto& [l, st] : s.by_level) o += "  level " + std::to_string(l) + ":  " + statsLine(st) + "\n";
  for (const auto& [a, st] : s.by_age) {
    std::snprintf(b, sizeof(b), "  age %-6s ", a.c_str());
    o += b + statsLine(st) + "\n";
  }
  return o;
}

std::string formatBackendLine(const FeatureTruthSummary& s) {
  char b[256];
  std::snprintf(b, sizeof(b), "backend per image: observations used %.1f, landmarks in window %.1f, "
                "outliers removed %.2f\n", s.backend_observations, s.backend_landmarks,
                s.backend_outliers_per_image);
  return b;
}

std::string formatSummary(const FeatureTruthSummary& s, const ImageRunOutput& run) {
  std::string o = formatErrorSummary(s, run, "feature error vs true projection", -1);
  char b[512];
  o += "by the class of the landmark's first observation (landmarks; observations after the first):\n";
  for (int k = 0; k < kNumCornerKinds; ++k) {
    std::snprintf(b, sizeof(b), "  %-9s %6d  ", cornerKindName(static_cast<CornerKind>(k)), s.landmarks_by_corner[k]);
    o += b + statsLine(s.by_corner[k]) + "\n";
  }
  o += "observations > 5 px [%] (count) by flight time [s] and class:\n";
  for (const auto& row : s.by_span) {
    std::snprintf(b, sizeof(b), "  %-6s", row.span.c_str());
    o += b;
    for (int k = 0; k < kNumCornerKinds; ++k) {
      std::snprintf(b, sizeof(b), "  %s %5.1f (%d)", cornerKindName(static_cast<CornerKind>(k)),
                    100 * row.by_corner[k].frac_above_5px, row.by_corner[k].count);
      o += b;
    }
    o += "\n";
  }
  std::snprintf(b, sizeof(b), "new landmarks per keyframe %.1f (unconverged %.1f%%), converged depth error "
                "median %.2f%% p90 %.2f%%\n", s.new_landmarks_per_keyframe, 100 * s.new_unconverged_fraction,
                100 * s.new_depth_error_median, 100 * s.new_depth_error_p90);
  o += b;
  return o + formatBackendLine(s);
}

}  // namespace hdvio
