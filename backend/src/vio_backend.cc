#include "hdvio/backend/vio_backend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hdvio/backend/triangulation.h"
#include "hdvio/core/thread_clock.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/prior_factors.h"
#include "hdvio/factors/reprojection_factor.h"

namespace hdvio {
using symbols::B;
using symbols::L;
using symbols::V;
using symbols::X;

namespace {
SmootherOptions smootherOptions(const VioBackendOptions& o) {
  SmootherOptions s;
  s.optimizer.max_iterations = o.max_iterations;
  s.optimizer.max_time_s = o.max_solver_time_s;
  s.optimizer.linear_solver = o.linear_solver;
  s.optimizer.optimizer = o.optimizer;
  if (o.landmarks_first) s.optimizer.eliminate_first = {L(0).letter()};
  s.optimizer.function_tolerance = o.function_tolerance;
  s.optimizer.initial_trust_region_radius = o.initial_trust_region_radius;
  if (o.trust_region_warm_start) {
    s.warm_start_min_radius = o.initial_trust_region_radius;
    s.warm_start_max_radius = o.max_trust_region_radius;
  }
  return s;
}
}  // namespace

VioBackend::VioBackend(const VioBackendOptions& options, const CameraModel& camera,
                       const Pose& T_BC, ResidualForceSource residual_force)
    : options_(options),
      camera_(camera),
      T_BC_(T_BC),
      dynamics_(makeDynamicsModel(options, std::move(residual_force))),
      smoother_(smootherOptions(options)) {}

void VioBackend::addImu(const ImuSample& s) {
  if (imu_.empty() || s.t > imu_.back().t) imu_.push_back(s);
}

void VioBackend::addThrust(const ThrustSample& s) {
  if (thrust_.empty() || s.t > thrust_.back().t) thrust_.push_back(s);
}

void VioBackend::initialize(const NavState& s) {
  initialize(s, {options_.init_velocity_sigma, options_.init_tilt_sigma});
}

void VioBackend::initialize(const NavState& s, const StartUncertainty& start) {
  if (!(start.velocity_sigma > 0.0) || !(start.tilt_sigma > 0.0))
    throw std::invalid_argument("VioBackend::initialize: start sigmas must be positive");
  const std::uint64_t k = next_index_++;
  Values values;
  FactorGraph priors;
  values.insertPose(X(k), s.T_WB);
  values.insertVector(V(k), s.v_W);
  values.insertVector(B(k), s.bias);
  // Gauge: position and yaw are fixed by the prior; tilt is observable through gravity.
  // The rotation tangent is in the body frame, so rotate the world-frame covariance into it.
  const Mat3 R = s.T_WB.R();
  const Vec3 rot_var(start.tilt_sigma * start.tilt_sigma, start.tilt_sigma * start.tilt_sigma,
                     options_.init_yaw_sigma * options_.init_yaw_sigma);
  Eigen::MatrixXd pose_cov = Eigen::MatrixXd::Zero(6, 6);
  pose_cov.topLeftCorner<3, 3>() =
      Mat3::Identity() * options_.init_position_sigma * options_.init_position_sigma;
  pose_cov.bottomRightCorner<3, 3>() = R.transpose() * rot_var.asDiagonal() * R;
  priors.add(std::make_shared<PosePrior>(X(k), s.T_WB, NoiseModel::covariance(pose_cov)));
  priors.add(std::make_shared<VelocityPrior>(
      V(k), s.v_W, NoiseModel::isotropic(3, start.velocity_sigma)));
  Eigen::VectorXd bias_sigmas(6);
  bias_sigmas << Vec3::Constant(options_.init_gyro_bias_sigma),
      Vec3::Constant(options_.init_accel_bias_sigma);
  priors.add(std::make_shared<BiasPrior>(B(k), s.bias, NoiseModel::diagonal(bias_sigmas)));
  std::map<Key, Timestamp> times{{X(k), s.t}, {V(k), s.t}, {B(k), s.t}};
  dynamics_->addFirstState(k, s, buffers(), &priors, &values);
  for (Key key : dynamics_->stateKeys(k)) times[key] = s.t;
  smoother_.update(priors, values, times, /*optimize=*/false);
  states_.push_back({k, s.t, true});
  last_keyframe_ = k;
}

NavState VioBackend::stateAt(std::uint64_t index, Timestamp t) const {
  const Values& est = smoother_.estimate();
  NavState s;
  s.t = t;
  s.T_WB = est.pose(X(index));
  s.v_W = est.vec3(V(index));
  s.bias = est.vector(B(index));
  dynamics_->readState(est, index, &s);
  return s;
}

NavState VioBackend::latestState() const {
  NavState s = stateAt(states_.back().index, states_.back().t);
  if (states_.size() >= 2)
    dynamics_->readNewest(smoother_.estimate(), states_[states_.size() - 2].index, &s);
  return s;
}

std::optional<Vec3> VioBackend::landmarkPosition(int landmark_id) const {
  const auto it = tracks_.find(landmark_id);
  if (it == tracks_.end()) return std::nullopt;
  const Values& est = smoother_.estimate();
  if (!it->second.in_graph || !est.exists(L(landmark_id))) return std::nullopt;
  return est.vec3(L(landmark_id));
}

std::vector<VioBackend::WindowPose> VioBackend::windowPoses() const {
  std::vector<WindowPose> out;
  for (const auto& slot : states_) out.push_back({slot.t, smoother_.estimate().pose(X(slot.index))});
  return out;
}

Pose VioBackend::cameraPose(std::uint64_t index) const {
  return smoother_.estimate().pose(X(index)) * T_BC_;
}

void VioBackend::addInertialFactors(const StateSlot& from, std::uint64_t k, Timestamp t,
                                    FactorGraph* graph, Values* values) {
  const std::uint64_t i = from.index;
  const NavState s = stateAt(i, from.t);
  auto pim = std::make_shared<const PreintegratedImu>(
      PreintegratedImu::integrate(imu_, from.t, t, s.bias, options_.imu));
  const double dt = pim->dt();
  const Vec3 g = options_.imu.gravity;
  const Mat3 Ri = s.T_WB.R();
  // Predict the new state with the IMU (and the current external-force estimate is ignored:
  // the accelerometer already measures it).
  const Pose T_j(Quat(Ri * pim->deltaR()), s.T_WB.p + s.v_W * dt + 0.5 * g * dt * dt +
                                              Ri * pim->deltaP());
  const Vec3 v_j = s.v_W + g * dt + Ri * pim->deltaV();
  values->insertPose(X(k), T_j);
  values->insertVector(V(k), v_j);
  values->insertVector(B(k), s.bias);
  graph->add(std::make_shared<ImuFactor>(X(i), V(i), B(i), X(k), V(k), B(k), pim));
  dynamics_->addInterval({i, k, from.t, t, s, v_j, dt}, buffers(), graph, values);
}

FrameResult VioBackend::addFrame(const FrameObservations& frame) {
  FrameResult result;
  if (!initialized() || imu_.empty() || imu_.back().t < frame.t || frame.t <= states_.back().t)
    return result;
  if (dynamics_->needsThrust() && (thrust_.empty() || thrust_.back().t < frame.t))
    return result;
  const double cpu_start = threadCpuSeconds();
  const std::uint64_t k = next_index_++;
  FactorGraph inertial;
  Values values;
  addInertialFactors(states_.back(), k, frame.t, &inertial, &values);
  std::map<Key, Timestamp> times{{X(k), frame.t}, {V(k), frame.t}, {B(k), frame.t}};
  for (Key key : dynamics_->stateKeys(k)) times[key] = frame.t;
  smoother_.update(inertial, values, times, /*optimize=*/false);
  states_.push_back({k, frame.t, false});

  addVisualFactors(k, frame, &result);
  states_.back().keyframe = isKeyframe(k);
  if (states_.back().keyframe) last_keyframe_ = k;

  const std::uint64_t oldest = states_.front().index;
  const Pose oldest_before = smoother_.estimate().pose(X(oldest));
  auto solved = smoother_.optimize();
  result.solves_usable = solved.usable;
  result.outliers_removed = rejectOutliers();
  if (result.outliers_removed > 0) {
    solved = smoother_.optimize();
    result.solves_usable = result.solves_usable && solved.usable;
  }
  result.solver_iterations = solved.iterations;
  result.solve_time_s = solved.solve_time_s;
  result.solve_converged = solved.converged;
  if (!solved.converged) holdGauge(oldest, oldest_before);
  const double window_start = threadCpuSeconds();
  maintainWindow();
  result.marginalization_cpu_s = threadCpuSeconds() - window_start;

  result.processed = true;
  result.keyframe = states_.back().keyframe;
  for (const auto& [id, track] : tracks_) result.landmarks_in_window += track.in_graph ? 1 : 0;
  result.state = latestState();
  result.cpu_time_s = threadCpuSeconds() - cpu_start;
  return result;
}

void VioBackend::addVisualFactors(std::uint64_t k, const FrameObservations& frame,
                                  FrameResult* result) {
  FactorGraph graph;
  std::vector<int> ids;
  std::vector<int> pending;
  for (const auto& f : frame.features) {
    Track& track = tracks_[f.landmark_id];
    track.obs[k] = f;
    if (track.in_graph) {
      // An observation the estimate cannot project (the landmark behind the camera) would fail
      // the whole solve: it is an outlier before the solve, as rejectOutliers would drop it after.
      FactorPtr factor = reprojectionFactor(k, f);
      Eigen::VectorXd r;
      if (!factor->whitenedError(smoother_.estimate(), &r)) {
        track.obs.erase(k);
        continue;
      }
      graph.add(std::move(factor));
      ids.push_back(f.landmark_id);
    } else {
      pending.push_back(f.landmark_id);
    }
  }
  const auto added = smoother_.update(graph, Values(), {}, /*optimize=*/false);
  for (std::size_t n = 0; n < ids.size(); ++n) tracks_[ids[n]].factors[k] = added.new_factor_ids[n];
  result->observations_used = static_cast<int>(ids.size());

  // New landmarks within the budget, longest tracks first (best parallax, most constraints).
  int in_window = 0;
  for (const auto& kv : tracks_) in_window += kv.second.in_graph ? 1 : 0;
  std::vector<std::pair<std::size_t, Track*>> candidates;  // (track length, track), frame order
  candidates.reserve(pending.size());
  for (int id : pending) candidates.emplace_back(tracks_[id].obs.size(), &tracks_[id]);
  std::vector<std::size_t> order(pending.size());
  for (std::size_t n = 0; n < order.size(); ++n) order[n] = n;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return candidates[a].first > candidates[b].first;
  });
  for (std::size_t n : order) {
    if (in_window >= options_.max_landmarks) break;
    const int id = pending[n];
    Track& track = *candidates[n].second;
    if (!tryTriangulate(id, &track)) continue;
    result->observations_used += 1;
    ++in_window;
  }
}

bool VioBackend::tryTriangulate(int id, Track* track) {
  if (static_cast<int>(track->obs.size()) < options_.min_observations) return false;
  std::vector<Pose> poses;
  std::vector<Vec3> rays;
  for (const auto& [index, o] : track->obs) {
    poses.push_back(cameraPose(index));
    rays.push_back(camera_.unproject(o.uv));
  }
  const TriangulationResult tri = triangulate(poses, rays);
  if (!tri.valid || tri.max_ray_angle_rad < options_.min_triangulation_angle_deg * M_PI / 180.0)
    return false;
  return insertLandmark(id, tri.p_W, track);
}

bool VioBackend::insertLandmark(int id, const Vec3& p_W, Track* track) {
  if (track->obs.empty()) return false;
  Values values;
  values.insertVector(L(id), p_W);
  FactorGraph graph;
  std::vector<std::uint64_t> order;
  for (const auto& [index, o] : track->obs) {
    graph.add(reprojectionFactor(index, o));
    order.push_back(index);
  }
  const auto added = smoother_.update(graph, values, {}, /*optimize=*/false);
  track->factors.clear();
  for (std::size_t n = 0; n < order.size(); ++n) track->factors[order[n]] = added.new_factor_ids[n];
  track->in_graph = true;
  return true;
}

FactorPtr VioBackend::reprojectionFactor(std::uint64_t index, const FeatureObservation& obs) const {
  return std::make_shared<ReprojectionFactor>(
      X(index), L(obs.landmark_id), obs.uv, camera_, T_BC_,
      pixelNoise(options_.pixel_sigma, options_.robust_loss, options_.robust_width_px));
}

bool VioBackend::isKeyframe(std::uint64_t k) const {
  if (!last_keyframe_) return true;
  std::vector<double> parallax;
  int seen_by_keyframe = 0;
  for (const auto& [id, track] : tracks_) {
    const auto kf = track.obs.find(*last_keyframe_);
    if (kf == track.obs.end()) continue;
    ++seen_by_keyframe;
    const auto now = track.obs.find(k);
    if (now != track.obs.end()) parallax.push_back((now->second.uv - kf->second.uv).norm());
  }
  if (parallax.size() < 8) return true;
  if (parallax.size() < options_.keyframe_min_tracked_ratio * seen_by_keyframe) return true;
  std::nth_element(parallax.begin(), parallax.begin() + parallax.size() / 2, parallax.end());
  return parallax[parallax.size() / 2] > options_.keyframe_parallax_px;
}

int VioBackend::rejectOutliers() {
  int removed = 0;
  std::set<Key> dead_landmarks;
  for (auto& [id, track] : tracks_) {
    if (!track.in_graph) continue;
    std::vector<SlidingWindowSmoother::FactorId> drop;
    for (auto it = track.factors.begin(); it != track.factors.end();) {
      Eigen::VectorXd r;
      const bool ok = smoother_.factor(it->second)->whitenedError(smoother_.estimate(), &r);
      if (!ok || r.norm() * options_.pixel_sigma > options_.outlier_threshold_px) {
        drop.push_back(it->second);
        track.obs.erase(it->first);
        it = track.factors.erase(it);
      } else {
        ++it;
      }
    }
    removed += static_cast<int>(drop.size());
    smoother_.removeFactors(drop);
    if (static_cast<int>(track.factors.size()) < options_.min_observations) {
      dead_landmarks.insert(L(id));
      track.factors.clear();
      track.in_graph = false;
    }
  }
  if (!dead_landmarks.empty()) smoother_.removeVariables(dead_landmarks);
  return removed;
}

void VioBackend::holdGauge(std::uint64_t index, const Pose& T_WB_before) {
  // The window's position and yaw are unobservable: only the start's prior, carried on by the
  // marginalizations and as weak as the drift is uncertain, holds them, so a solve stopped by its
  // iteration budget can have moved the whole window along them. Undo the oldest state's move in
  // position and yaw on the window and its priors together (docs/backend.md "The gauge"); the
  // relative corrections and the tilts stay as solved.
  smoother_.changeGauge(GaugeTransform::restoring(T_WB_before, smoother_.estimate().pose(X(index))));
}

void VioBackend::maintainWindow() {
  const std::size_t recent = static_cast<std::size_t>(options_.num_recent);
  // States older than the K most recent stay only if they are keyframes.
  for (std::size_t n = 0; n + recent < states_.size();) {
    if (!states_[n].keyframe) {
      marginalizeState(states_[n].index, /*keep_landmark_information=*/false);
    } else {
      ++n;
    }
  }
  auto old_keyframes = [&] {
    return states_.size() > recent ? static_cast<int>(states_.size() - recent) : 0;
  };
  while (old_keyframes() > options_.num_keyframes)
    marginalizeState(states_.front().index, /*keep_landmark_information=*/true);
}

void VioBackend::marginalizeState(std::uint64_t index, bool keep_landmark_information) {
  // Landmarks first seen by a leaving keyframe and no longer seen by the recent states leave
  // with it (their observations from the other keyframes go into the prior); landmarks still
  // tracked stay and only lose this observation (as OKVIS does). Other observations by the
  // leaving state are dropped too. So the prior links old keyframes only and stays small.
  std::set<Key> leaving{X(index), V(index), B(index)};
  for (Key key : dynamics_->stateKeys(index)) leaving.insert(key);
  const std::size_t recent = std::min(states_.size(), static_cast<std::size_t>(options_.num_recent));
  const std::uint64_t first_recent = states_[states_.size() - recent].index;
  std::set<std::uint64_t> keyframes;
  for (const auto& slot : states_)
    if (slot.keyframe) keyframes.insert(slot.index);
  const auto keyframe_of = [&](std::uint64_t i) { return keyframes.count(i) > 0; };
  std::set<Key> dead_landmarks;
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    Track& track = it->second;
    const bool observed = track.obs.count(index) > 0;
    const bool still_tracked = !track.factors.empty() && track.factors.rbegin()->first >= first_recent;
    const LandmarkMarginalization rule = options_.landmark_marginalization;
    if (observed && track.in_graph && keep_landmark_information &&
        !(rule == LandmarkMarginalization::kUntracked && still_tracked) &&
        track.obs.begin()->first == index && track.factors.count(index)) {
      if (rule == LandmarkMarginalization::kKeyframes) {
        for (auto f = track.factors.begin(); f != track.factors.end();) {
          if (keyframe_of(f->first)) {
            ++f;
            continue;
          }
          smoother_.removeFactors({f->second});
          f = track.factors.erase(f);
        }
      }
      leaving.insert(L(it->first));
      it = tracks_.erase(it);
      continue;
    }
    track.obs.erase(index);
    const auto f = track.factors.find(index);
    if (f != track.factors.end()) {
      smoother_.removeFactors({f->second});
      track.factors.erase(f);
    }
    if (track.in_graph && static_cast<int>(track.factors.size()) < options_.min_observations) {
      dead_landmarks.insert(L(it->first));
      track.factors.clear();
      track.in_graph = false;
    }
    it = (track.obs.empty() && !track.in_graph) ? tracks_.erase(it) : std::next(it);
  }
  if (!dead_landmarks.empty()) smoother_.removeVariables(dead_landmarks);
  smoother_.marginalize(leaving);
  states_.erase(std::find_if(states_.begin(), states_.end(),
                             [&](const StateSlot& s) { return s.index == index; }));
  if (last_keyframe_ == index) last_keyframe_.reset();
}

}  // namespace hdvio
