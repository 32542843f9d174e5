#include "hdvio/backend/imo/imo_filter.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace hdvio::imo {
namespace {

constexpr int kTheta = 0, kVel = 3, kPos = 6, kBg = 9, kBa = 12;
constexpr double kChi2Threshold3Dof = 11.345;  // 99 % quantile, 3 dof
constexpr int kInitialCapacity = kStateDim + 16 * kCloneDim;  // a 0.5 s window at 20 Hz and more

int cloneOffset(int k) { return kStateDim + kCloneDim * k; }

// Re-orthonormalize through a unit quaternion (cheaper than an SVD at IMU rate).
Mat3 orthonormalized(const Mat3& R) { return Quat(R).normalized().toRotationMatrix(); }

// The covariance loops below are plain C++ compiled twice (AVX2 and plain x86-64, picked at
// load time): without fused multiply-adds both give the same doubles as Eigen's SSE2 code of
// the same expressions (same operations in the same order).

// Columns first..end-1 of the top 15 rows of P become phi (15 x 15, column-major) times them,
// and rows first..end-1 of the first 15 columns their transpose: one column at a time as 15
// axpys (no heap, no GEMM set-up for 15 rows).
__attribute__((target_clones("avx2", "default"))) void applyToColumns(const double* phi, double* P,
                                                                      long stride, int first, int end) {
  for (int c = first; c < end; ++c) {
    double* col = P + c * stride;
    double out[kStateDim] = {};
    for (int k = 0; k < kStateDim; ++k) {
      const double v = col[k];
      for (int i = 0; i < kStateDim; ++i) out[i] += phi[k * kStateDim + i] * v;
    }
    for (int i = 0; i < kStateDim; ++i) {
      col[i] = out[i];
      P[i * stride + c] = out[i];
    }
  }
}

// P -= K U' + U K' on the lower triangle of the n x n column-major P (leading dimension
// stride); K and U are n x 3, column-major.
__attribute__((target_clones("avx2", "default"))) void subtractSymmetricRank6(
    double* P, long stride, int n, const double* K, const double* U) {
  const double *K0 = K, *K1 = K + n, *K2 = K + 2 * n, *U0 = U, *U1 = U + n, *U2 = U + 2 * n;
  for (int c = 0; c < n; ++c) {
    const double u0 = U0[c], u1 = U1[c], u2 = U2[c], k0 = K0[c], k1 = K1[c], k2 = K2[c];
    double* col = P + c * stride;
    for (int r = c; r < n; ++r)
      col[r] -= u0 * K0[r] + u1 * K1[r] + u2 * K2[r] + k0 * U0[r] + k1 * U1[r] + k2 * U2[r];
  }
}

// Upper triangle = lower triangle, in 4 x 4 tiles: each tile reads four short runs of the lower
// triangle and writes four short runs of the upper one (a plain loop reads one element per
// cache line).
__attribute__((target_clones("avx2", "default"))) void mirrorLowerTriangle(double* P, long stride, int n) {
  constexpr int kTile = 4;
  for (int c0 = 0; c0 < n; c0 += kTile) {
    const int c1 = std::min(n, c0 + kTile);
    for (int r0 = 0; r0 < c1; r0 += kTile) {
      const int r1 = std::min(c1 - 1, r0 + kTile);  // rows r < c only
      for (int r = r0; r < r1; ++r) {
        const double* lower = P + r * stride;  // column r: element (c, r) at lower[c]
        for (int c = std::max(c0, r + 1); c < c1; ++c) P[c * stride + r] = lower[c];
      }
    }
  }
}

}  // namespace

PropagationStep propagateNominal(const ImoNominalState& x, const Vec3& gyro, const Vec3& accel,
                                 double dt, const Vec3& gravity, bool start_attitude,
                                 RotationError rotation_error) {
  const NominalStep s = propagateStep(x, gyro, accel, dt, gravity, start_attitude, rotation_error);
  return {s.state, s.transition.dense(), s.transition.noiseInput()};
}

ImoFilter::ImoFilter(const ImoFilterOptions& options) : options_(options) {}

void ImoFilter::initialize(const ImoNominalState& x0) {
  x_ = x0;
  clones_.clear();
  P_ = MatX::Zero(kInitialCapacity, kInitialCapacity);
  const auto& o = options_;
  P_.diagonal().segment<3>(kTheta) << o.init_attitude_sigma * o.init_attitude_sigma,
      o.init_attitude_sigma * o.init_attitude_sigma, o.init_yaw_sigma * o.init_yaw_sigma;
  P_.diagonal().segment<3>(kVel).setConstant(o.init_velocity_sigma * o.init_velocity_sigma);
  P_.diagonal().segment<3>(kPos).setConstant(o.init_position_sigma * o.init_position_sigma);
  P_.diagonal().segment<3>(kBg).setConstant(o.init_gyro_bias_sigma * o.init_gyro_bias_sigma);
  P_.diagonal().segment<3>(kBa).setConstant(o.init_accel_bias_sigma * o.init_accel_bias_sigma);
  phi_.setIdentity();
}

void ImoFilter::propagate(const Vec3& gyro, const Vec3& accel, Timestamp t_next) {
  const double dt = secondsBetween(x_.t, t_next);
  if (dt < 0.0) throw std::logic_error("ImoFilter::propagate: time goes backwards");
  if (dt == 0.0) return;
  const NominalStep s = propagateStep(x_, gyro, accel, dt, options_.gravity, options_.release_propagation,
                                      options_.rotation_error);
  x_ = s.state;
  x_.t = t_next;

  // Discrete noise from densities: a white sample held over dt has variance sigma^2 / dt.
  const auto& o = options_;
  Mat15 Pee = P_.topLeftCorner<kStateDim, kStateDim>();
  propagateCovariance(s.transition, o.gyro_noise_density * o.gyro_noise_density / dt,
                      o.accel_noise_density * o.accel_noise_density / dt, &Pee);
  Pee.diagonal().segment<3>(kBg).array() += o.gyro_random_walk * o.gyro_random_walk * dt;
  Pee.diagonal().segment<3>(kBa).array() += o.accel_random_walk * o.accel_random_walk * dt;
  P_.topLeftCorner<kStateDim, kStateDim>() = 0.5 * (Pee + Pee.transpose());
  applyTransition(s.transition, &phi_);  // phi_ <- A phi_
}

void ImoFilter::syncCrossCovariance() {
  const int nc = dim() - kStateDim;
  if (nc > 0 && !phi_.isIdentity(0.0)) {
    applyToColumns(phi_.data(), P_.data(), P_.rows(), kStateDim, kStateDim + nc);
  }
  phi_.setIdentity();
}

MatX ImoFilter::covariance() const {
  MatX P = cov();
  const int nc = dim() - kStateDim;
  if (nc > 0) {
    const MatX cross = phi_ * P.topRightCorner(kStateDim, nc);
    P.topRightCorner(kStateDim, nc) = cross;
    P.bottomLeftCorner(nc, kStateDim) = cross.transpose();
  }
  return P;
}

void ImoFilter::reserve(int n) {
  if (P_.rows() >= n) return;
  const int capacity = std::max(n, 2 * static_cast<int>(P_.rows()));
  MatX P = MatX::Zero(capacity, capacity);
  P.topLeftCorner(dim(), dim()) = cov();
  P_ = std::move(P);
}

void ImoFilter::addClone() {
  syncCrossCovariance();
  const int n = dim();
  reserve(n + kCloneDim);
  // The clone is the first 9 evolving rows; source and destination blocks are disjoint (n > 9).
  P_.block(n, 0, kCloneDim, n) = P_.block(0, 0, kCloneDim, n);
  P_.block(0, n, n, kCloneDim) = P_.block(0, 0, n, kCloneDim);
  P_.block(n, n, kCloneDim, kCloneDim) = P_.block(0, 0, kCloneDim, kCloneDim);
  clones_.push_back({x_.t, x_.R, x_.v, x_.p});
}

void ImoFilter::marginalizeClone(int k) {
  if (k < 0 || k >= static_cast<int>(clones_.size()))
    throw std::logic_error("ImoFilter::marginalizeClone: no such clone");
  syncCrossCovariance();
  const int n = dim();
  const int o = cloneOffset(k);
  const int tail = n - o - kCloneDim;
  // In place, column by column in increasing order: column c of the result is column c (c < o)
  // or c + 9 of the storage, which has not been overwritten yet; rows o + 9.. move up by 9.
  const long stride = P_.rows();
  double* data = P_.data();
  for (int c = 0; c < n - kCloneDim; ++c) {
    double* dst = data + c * stride;
    const double* src = data + (c < o ? c : c + kCloneDim) * stride;
    if (src != dst) std::memcpy(dst, src, sizeof(double) * static_cast<std::size_t>(o));
    std::memmove(dst + o, src + o + kCloneDim, sizeof(double) * static_cast<std::size_t>(tail));
  }
  clones_.erase(clones_.begin() + k);
}

int ImoFilter::findClone(Timestamp t) const {
  for (std::size_t k = 0; k < clones_.size(); ++k)
    if (clones_[k].t == t) return static_cast<int>(k);
  return -1;
}

Vec3 ImoFilter::predictMeasurement(const RelativePositionMeasurement& m) const {
  const ImoClone& ci = clones_.at(m.clone_i);
  const ImoClone& cj = clones_.at(m.clone_j);
  // The attitude term is zero at the estimate.
  return cj.p - ci.p - m.velocity_coefficient * ci.v - m.velocity_matrix * ci.v;
}

MatX ImoFilter::measurementJacobian(const RelativePositionMeasurement& m) const {
  MatX H = MatX::Zero(3, dim());
  H.block<3, 3>(0, cloneOffset(m.clone_j) + kPos) += Mat3::Identity();
  H.block<3, 3>(0, cloneOffset(m.clone_i) + kPos) -= Mat3::Identity();
  H.block<3, 3>(0, cloneOffset(m.clone_i) + kVel) -=
      m.velocity_coefficient * Mat3::Identity() + m.velocity_matrix;
  H.block<3, 3>(0, cloneOffset(m.clone_i) + kTheta) -= attitudeBlock(m.attitude_jacobian, clones_.at(m.clone_i).R);
  return H;
}

UpdateOutcome ImoFilter::update(const RelativePositionMeasurement& m) {
  if (m.clone_i < 0 || m.clone_j < 0 || m.clone_i >= static_cast<int>(clones_.size()) ||
      m.clone_j >= static_cast<int>(clones_.size()) || m.clone_i == m.clone_j)
    throw std::logic_error("ImoFilter::update: bad clone indices");
  syncCrossCovariance();
  // H has at most four 3x3 blocks: P H^T is a combination of column blocks of P.
  const int oi = cloneOffset(m.clone_i), oj = cloneOffset(m.clone_j);
  const Mat3 C = m.velocity_coefficient * Mat3::Identity() + m.velocity_matrix;
  const Mat3 J = attitudeBlock(m.attitude_jacobian, clones_[m.clone_i].R);
  const bool has_c = !C.isZero(0.0), has_j = !J.isZero(0.0);
  const int n = dim();
  const auto P = cov();
  Eigen::Matrix<double, Eigen::Dynamic, 3> PHt = P.middleCols<3>(oj + kPos) - P.middleCols<3>(oi + kPos);
  if (has_c) PHt.noalias() -= P.middleCols<3>(oi + kVel) * C.transpose();
  if (has_j) PHt.noalias() -= P.middleCols<3>(oi + kTheta) * J.transpose();
  Mat3 HPHt = PHt.middleRows<3>(oj + kPos) - PHt.middleRows<3>(oi + kPos);
  if (has_c) HPHt -= C * PHt.middleRows<3>(oi + kVel);
  if (has_j) HPHt -= J * PHt.middleRows<3>(oi + kTheta);
  Mat3 S = HPHt + m.covariance;
  S = 0.5 * (S + S.transpose());
  const Vec3 r = m.z - predictMeasurement(m);
  const Eigen::LDLT<Mat3> S_ldlt(S);
  last_chi2_ = r.dot(S_ldlt.solve(r));
  last_innovation_ = {r, S, last_chi2_};
  if (options_.mahalanobis_factor > 0.0 &&
      last_chi2_ > options_.mahalanobis_factor * kChi2Threshold3Dof)
    return UpdateOutcome::kRejectedByGate;

  // K = P H' S^-1 and K S below as lazy (coefficient-wise) products: GEMM and triangular-solve
  // set-up would cost more than the n x 3 x 3 multiply-adds.
  const Mat3 S_inv = S_ldlt.solve(Mat3::Identity());
  const Eigen::Matrix<double, Eigen::Dynamic, 3> K = PHt.lazyProduct(S_inv);
  // Joseph form (I - KH) P (I - KH)' + K R K', expanded with P H' so it costs O(n^2):
  // P - K H P - P H' K' + K S K' = P - (K U' + U K') with U = P H' - K S / 2. The lower
  // triangle is updated column by column (six axpys each) and mirrored, so the result is
  // symmetric by construction and nothing n x n is allocated.
  const Eigen::Matrix<double, Eigen::Dynamic, 3> U = PHt - 0.5 * K.lazyProduct(S);
  subtractSymmetricRank6(P_.data(), P_.rows(), n, K.data(), U.data());
  mirrorLowerTriangle(P_.data(), P_.rows(), n);
  inject(K.lazyProduct(r));
  return UpdateOutcome::kApplied;
}

Mat3 ImoFilter::attitudeBlock(const Mat3& J_right, const Mat3& R) const {
  // R_hat Exp(d_right) = Exp(d_left) R_hat with d_right = R_hat^T d_left.
  return options_.rotation_error == RotationError::kLeft ? Mat3(J_right * R.transpose()) : J_right;
}

Mat3 ImoFilter::perturbed(const Mat3& R, const Vec3& dtheta) const {
  return orthonormalized(options_.rotation_error == RotationError::kLeft ? Mat3(so3Exp(dtheta) * R)
                                                                        : Mat3(R * so3Exp(dtheta)));
}

void ImoFilter::inject(const VecX& dx) {
  if (dx.size() != dim()) throw std::logic_error("ImoFilter::inject: wrong size");
  x_.R = perturbed(x_.R, dx.segment<3>(kTheta));
  x_.v += dx.segment<3>(kVel);
  x_.p += dx.segment<3>(kPos);
  x_.bg += dx.segment<3>(kBg);
  x_.ba += dx.segment<3>(kBa);
  for (std::size_t k = 0; k < clones_.size(); ++k) {
    const int o = cloneOffset(static_cast<int>(k));
    clones_[k].R = perturbed(clones_[k].R, dx.segment<3>(o + kTheta));
    clones_[k].v += dx.segment<3>(o + kVel);
    clones_[k].p += dx.segment<3>(o + kPos);
  }
}

}  // namespace hdvio::imo
