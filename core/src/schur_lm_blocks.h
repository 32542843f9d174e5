#pragma once
// The block kernels of schur_lm.cc: Schur-complement products, J^T J of small factors with
// fixed sizes for the usual blocks, and Ceres' robust-loss correction. Internal to core/src.
#include <cmath>

#include <Eigen/Core>
#include <ceres/loss_function.h>

namespace hdvio::schur_lm_blocks {

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMap = Eigen::Map<RowMat>;
using ConstRowMap = Eigen::Map<const RowMat>;
using ConstVecMap = Eigen::Map<const Eigen::VectorXd>;

// S(R x C block at s, column-major, leading dimension ld) -= V W^T for a 3-wide eliminated
// variable (a landmark): V given by columns (Vt: R x 3, column-major), W (C x 3) row-major. Each
// column of the block takes V times one row of W as whole columns of V, which vectorizes, where
// a coefficient-wise product computes 3-long dot products one by one. The sums are formed in
// the same order ((v0 w0 + v1 w1) + v2 w2), so the results are the same bits.
template <int R, int C>
inline void subtractColumns3(double* s, Eigen::Index ld, const double* Vt, const double* W) {
  using Col = Eigen::Matrix<double, R, 1>;
  const Eigen::Map<const Col> v0(Vt), v1(Vt + R), v2(Vt + 2 * R);
  for (int c = 0; c < C; ++c) {
    Eigen::Map<Col> col(s + c * ld);
    const double* w = W + 3 * c;
    col.noalias() -= v0 * w[0] + v1 * w[1] + v2 * w[2];
  }
}

// Vt (rows x 3, column-major) from V (rows x 3, row-major) for the kernel above; false (nothing
// written) unless rows is 3 or 6.
inline bool landmarkColumns(const double* V, int rows, double* Vt) {
  if (rows != 3 && rows != 6) return false;
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < 3; ++k) Vt[k * rows + r] = V[r * 3 + k];
  return true;
}

// subtractColumns3 on S's block at (i, j) for blocks of 3 or 6; false (nothing done) otherwise.
inline bool subtractColumns3(Eigen::MatrixXd* S, int i, int j, int rows, int cols, const double* Vt,
                             const double* W) {
  double* s = S->data() + i + static_cast<Eigen::Index>(j) * S->rows();
  const Eigen::Index ld = S->rows();
  if (rows == 6 && cols == 6) return subtractColumns3<6, 6>(s, ld, Vt, W), true;
  if (rows == 6 && cols == 3) return subtractColumns3<6, 3>(s, ld, Vt, W), true;
  if (rows == 3 && cols == 6) return subtractColumns3<3, 6>(s, ld, Vt, W), true;
  if (rows == 3 && cols == 3) return subtractColumns3<3, 3>(s, ld, Vt, W), true;
  return false;
}

// A landmark's V = W A^-1 (R x 3, row-major, W too) and rhs_v += V g, with fixed sizes (the
// products of the dynamic-size path, in the same order).
template <int R>
inline void landmarkV(const double* W, const double* A_inv, const double* g, double* V, double* rhs_v) {
  using RowR3 = Eigen::Matrix<double, R, 3, Eigen::RowMajor>;
  Eigen::Map<RowR3> v(V);
  v.noalias() = Eigen::Map<const RowR3>(W).lazyProduct(Eigen::Map<const Eigen::Matrix3d>(A_inv));
  Eigen::Map<Eigen::Matrix<double, R, 1>>(rhs_v).noalias() += v.lazyProduct(Eigen::Map<const Eigen::Vector3d>(g));
}

// S(rows x cols block at S_ij) -= V W^T with V (rows x e) and W (cols x e) row-major: the
// Schur complement's inner product for blocks the landmark kernels above do not take.
inline void subtractProduct(Eigen::MatrixXd* S, int i, int j, int rows, int cols, int e, const double* V,
                     const double* W) {
  const ConstRowMap v(V, rows, e), w(W, cols, e);
  S->block(i, j, rows, cols).noalias() -= v.lazyProduct(w.transpose());
}

// out (ta x tc, at out_ptr with outer stride ld, column-major) += Ja^T Jc, Ja (dim x ta) and Jc
// (dim x tc) row-major; fixed sizes for a reprojection's 2 rows and 3- or 6-wide blocks.
template <int D, int TA, int TC>
inline void addJtJFixed(double* out, int ld, const double* Ja, const double* Jc) {
  Eigen::Map<const Eigen::Matrix<double, D, TA, Eigen::RowMajor>> a(Ja);
  Eigen::Map<const Eigen::Matrix<double, D, TC, Eigen::RowMajor>> c(Jc);
  Eigen::Map<Eigen::Matrix<double, TA, TC>, 0, Eigen::OuterStride<>> o(out, Eigen::OuterStride<>(ld));
  o.noalias() += a.transpose().lazyProduct(c);
}

// out = Ja^T Jc (the same products as addJtJ onto a zeroed block, without zeroing it first).
template <int D, int TA, int TC>
inline void setJtJFixed(double* out, const double* Ja, const double* Jc) {
  Eigen::Map<const Eigen::Matrix<double, D, TA, Eigen::RowMajor>> a(Ja);
  Eigen::Map<const Eigen::Matrix<double, D, TC, Eigen::RowMajor>> c(Jc);
  Eigen::Map<Eigen::Matrix<double, TA, TC>> o(out);
  o.noalias() = a.transpose().lazyProduct(c);
}

// out (ta x tc, column-major, contiguous) = Ja^T Jc.
inline void setJtJ(double* out, int dim, int ta, int tc, const double* Ja, const double* Jc) {
  if (dim == 2) {
    if (ta == 3 && tc == 6) return setJtJFixed<2, 3, 6>(out, Ja, Jc);
    if (ta == 3 && tc == 3) return setJtJFixed<2, 3, 3>(out, Ja, Jc);
  }
  const ConstRowMap a(Ja, dim, ta), c(Jc, dim, tc);
  Eigen::Map<Eigen::MatrixXd> o(out, ta, tc);
  o.noalias() = a.transpose().lazyProduct(c);
}

inline void addJtJ(double* out, int ld, int dim, int ta, int tc, const double* Ja, const double* Jc) {
  if (dim == 2) {
    if (ta == 6 && tc == 6) return addJtJFixed<2, 6, 6>(out, ld, Ja, Jc);
    if (ta == 6 && tc == 3) return addJtJFixed<2, 6, 3>(out, ld, Ja, Jc);
    if (ta == 3 && tc == 3) return addJtJFixed<2, 3, 3>(out, ld, Ja, Jc);
    if (ta == 3 && tc == 6) return addJtJFixed<2, 3, 6>(out, ld, Ja, Jc);
  }
  const ConstRowMap a(Ja, dim, ta), c(Jc, dim, tc);
  Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>> o(out, ta, tc, Eigen::OuterStride<>(ld));
  o.noalias() += a.transpose().lazyProduct(c);
}

// jd (2) += J dx for a 2-row factor's block J (2 x cols, row-major) of 3 or 6 columns; false
// (nothing done) otherwise. Summed as Eigen's dynamic-size row-major product sums with
// two-double packets (SSE2, NEON): even and odd columns in two lanes, then the lanes; so the
// model cost change is the same to the bit as with that product, without its dispatch.
inline bool addTwoRowProduct(double* jd, const double* J, int cols, const double* dx) {
  if (cols == 6) {
    for (int r = 0; r < 2; ++r) {
      const double* a = J + 6 * r;
      const double even = (a[0] * dx[0] + a[2] * dx[2]) + a[4] * dx[4];
      const double odd = (a[1] * dx[1] + a[3] * dx[3]) + a[5] * dx[5];
      jd[r] += even + odd;
    }
    return true;
  }
  if (cols == 3) {
    for (int r = 0; r < 2; ++r) {
      const double* a = J + 3 * r;
      jd[r] += (a[0] * dx[0] + a[1] * dx[1]) + a[2] * dx[2];
    }
    return true;
  }
  return false;
}

// t (3) -= W^T d for a landmark's W (rows x 3, row-major) with 3 or 6 rows; false (nothing
// done) otherwise. Each entry sums its products in row order before subtracting, as Eigen's
// dynamic-size column-major product does, so the back substitution keeps its bits.
inline bool subtractLandmarkWtd(double* t, const double* W, int rows, const double* d) {
  if (rows != 3 && rows != 6) return false;
  for (int c = 0; c < 3; ++c) {
    double sum = W[c] * d[0];
    for (int r = 1; r < rows; ++r) sum += W[3 * r + c] * d[r];
    t[c] -= sum;
  }
  return true;
}

// Ceres' Corrector (internal/ceres/corrector.cc): the robust loss as a rescaled residual and
// Jacobian, with the second-order term when rho'' > 0.
inline void applyLoss(const ceres::LossFunction& loss, int dim, double* r, double* const* J,
                      const int* cols, int num_keys, double* cost) {
  double s = 0.0;
  for (int i = 0; i < dim; ++i) s += r[i] * r[i];
  double rho[3];
  loss.Evaluate(s, rho);
  *cost += 0.5 * rho[0];
  if (!J) return;
  const double sqrt_rho1 = std::sqrt(rho[1]);
  double scaling = sqrt_rho1, alpha_sq_norm = 0.0;
  if (s != 0.0 && rho[2] > 0.0) {
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
    scaling = sqrt_rho1 / (1.0 - alpha);
    alpha_sq_norm = alpha / s;
  }
  for (int k = 0; k < num_keys; ++k) {
    if (!J[k]) continue;
    if (alpha_sq_norm == 0.0) {  // first order only (Huber): each entry times sqrt(rho')
      for (int i = 0; i < dim * cols[k]; ++i) J[k][i] *= sqrt_rho1;
    } else {
      RowMap Jk(J[k], dim, cols[k]);
      const ConstVecMap rv(r, dim);
      const Eigen::RowVectorXd rtj = rv.transpose() * Jk;
      Jk = sqrt_rho1 * (Jk - alpha_sq_norm * rv * rtj);
    }
  }
  for (int i = 0; i < dim; ++i) r[i] *= scaling;
}

}  // namespace hdvio::schur_lm_blocks
