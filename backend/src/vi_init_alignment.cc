#include "hdvio/backend/vi_init_alignment.h"

#include <Eigen/Dense>
#include <cmath>

#include "hdvio/core/sequence.h"

namespace hdvio::vi_init {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;
using Mat32 = Eigen::Matrix<double, 3, 2>;

// Stacks, for every interval k -> k+1 (R_k = R_C0B_k, p = camera positions up to scale s):
//   s (p_k+1 - p_k) - v_k dt - g dt^2/2 - R_k Jp_ba dba = R_k dp + (R_k+1 - R_k) p_BC
//   v_k+1 - v_k - g dt - R_k Jv_ba dba                  = R_k dv
// with gravity either free (basis null) or g = g0 + basis * w, and solves least squares.
AlignmentResult solveAlignment(const std::vector<AlignmentFrame>& frames,
                               const std::vector<PreintegratedImu>& preint, const Vec3& p_BC,
                               const Vec3& g0, const Mat32* basis, bool with_accel_bias,
                               double prior_row_weight) {
  const int n = static_cast<int>(frames.size());
  const int ng = basis ? 2 : 3;
  const int is = 3 * n + ng;  // scale
  const int iba = is + 1;
  const int cols = iba + (with_accel_bias ? 3 : 0);
  const int rows = 6 * (n - 1) + (with_accel_bias ? 3 : 0);
  MatX A = MatX::Zero(rows, cols);
  VecX b = VecX::Zero(rows);
  Eigen::Matrix3d G = Mat3::Identity();
  for (int k = 0; k + 1 < n; ++k) {
    const PreintegratedImu& pi = preint[k];
    const double dt = pi.dt();
    const Mat3& Rk = frames[k].R_C0B;
    const Mat3& Rk1 = frames[k + 1].R_C0B;
    const int r = 6 * k;
    A.block<3, 3>(r, 3 * k) = -dt * Mat3::Identity();
    A.block<3, 1>(r, is) = frames[k + 1].p_C0C - frames[k].p_C0C;
    b.segment<3>(r) = Rk * pi.deltaP() + (Rk1 - Rk) * p_BC;
    A.block<3, 3>(r + 3, 3 * k) = -Mat3::Identity();
    A.block<3, 3>(r + 3, 3 * k + 3) = Mat3::Identity();
    b.segment<3>(r + 3) = Rk * pi.deltaV();
    if (basis) {
      A.block<3, 2>(r, 3 * n) = -0.5 * dt * dt * *basis;
      A.block<3, 2>(r + 3, 3 * n) = -dt * *basis;
      b.segment<3>(r) += 0.5 * dt * dt * g0;
      b.segment<3>(r + 3) += dt * g0;
    } else {
      A.block<3, 3>(r, 3 * n) = -0.5 * dt * dt * G;
      A.block<3, 3>(r + 3, 3 * n) = -dt * G;
    }
    if (with_accel_bias) {
      A.block<3, 3>(r, iba) = -Rk * pi.dp_dba();
      A.block<3, 3>(r + 3, iba) = -Rk * pi.dv_dba();
    }
  }
  if (with_accel_bias) A.block<3, 3>(rows - 3, iba) = prior_row_weight * Mat3::Identity();

  const MatX AtA = A.transpose() * A;
  const Eigen::LDLT<MatX> ldlt(AtA);
  const VecX x = ldlt.solve(A.transpose() * b);
  const VecX res = A * x - b;
  AlignmentResult out;
  out.v_C0.resize(n);
  for (int k = 0; k < n; ++k) out.v_C0[k] = x.segment<3>(3 * k);
  out.g_C0 = basis ? Vec3(g0 + *basis * x.segment<2>(3 * n)) : Vec3(x.segment<3>(3 * n));
  out.scale = x(is);
  if (with_accel_bias) out.accel_bias_delta = x.segment<3>(iba);
  out.rms_residual = std::sqrt(res.squaredNorm() / rows);
  const double sigma2 = res.squaredNorm() / std::max(1, rows - cols);
  VecX e_s = VecX::Zero(cols);
  e_s(is) = 1.0;
  const double var_s = sigma2 * ldlt.solve(e_s)(is);
  out.scale_relative_std =
      std::abs(out.scale) > 0 ? std::sqrt(std::max(0.0, var_s)) / std::abs(out.scale) : 1e9;
  return out;
}

}  // namespace

Vec3 estimateGyroBias(const std::vector<AlignmentFrame>& frames,
                      const std::vector<PreintegratedImu>& preint) {
  // dR(bg) ~= dR Exp(J (bg - bg_lin)) = R_vis  ->  J dbg = Log(dR^T R_vis).
  Mat3 H = Mat3::Zero();
  Vec3 g = Vec3::Zero();
  for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
    const Mat3 R_vis = frames[k].R_C0B.transpose() * frames[k + 1].R_C0B;
    const Mat3& J = preint[k].dR_dbg();
    const Vec3 e = so3Log(preint[k].deltaR().transpose() * R_vis);
    H += J.transpose() * J;
    g += J.transpose() * (e + J * preint[k].bias().head<3>());
  }
  // Solved for the absolute bias: J (bg - bg_lin_k) = e_k  <=>  J bg = e_k + J bg_lin_k.
  return H.ldlt().solve(g);
}

Eigen::Matrix<double, 3, 2> tangentBasis(const Vec3& g) {
  const Vec3 a = g.normalized();
  Vec3 tmp = Vec3::UnitZ();
  if (std::abs(a.dot(tmp)) > 0.9) tmp = Vec3::UnitX();
  const Vec3 b1 = (tmp - a * a.dot(tmp)).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = b1;
  B.col(1) = a.cross(b1);
  return B;
}

AlignmentResult alignLinear(const std::vector<AlignmentFrame>& frames,
                            const std::vector<PreintegratedImu>& preint, const Vec3& p_BC) {
  return solveAlignment(frames, preint, p_BC, Vec3::Zero(), nullptr, false, 0.0);
}

AlignmentResult refineGravity(const std::vector<AlignmentFrame>& frames,
                              const std::vector<PreintegratedImu>& preint, const Vec3& p_BC,
                              const Vec3& g_init, const AlignmentOptions& options) {
  Vec3 g = kGravity * g_init.normalized();
  AlignmentResult out;
  for (int it = 0; it < std::max(1, options.refinement_iterations); ++it) {
    const Mat32 B = tangentBasis(g);
    out = solveAlignment(frames, preint, p_BC, g, &B, options.estimate_accel_bias,
                         options.equation_sigma / options.accel_bias_prior_sigma);
    g = kGravity * out.g_C0.normalized();
  }
  out.g_C0 = g;
  return out;
}

}  // namespace hdvio::vi_init
