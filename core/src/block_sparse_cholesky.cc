#include "hdvio/core/block_sparse_cholesky.h"

#include <algorithm>
#include <limits>

#include <Eigen/Cholesky>

namespace hdvio {
namespace {

// Block (i, j) of a matrix stored in its upper triangle, as a copy.
Eigen::MatrixXd blockOf(const Eigen::MatrixXd& S, int oi, int si, int oj, int sj) {
  if (oi <= oj) return S.block(oi, oj, si, sj);
  return S.block(oj, oi, sj, si).transpose();
}

// S (R x C at S_ptr, column-major with leading dimension ld) -= A B^T, A (R x K), B (C x K)
// column-major: fixed sizes for the window's 3- and 6-wide blocks.
template <int R, int C, int K>
void subtractFixed(double* S, int ld, const double* A, const double* B) {
  Eigen::Map<Eigen::Matrix<double, R, C>, 0, Eigen::OuterStride<>> s(S, Eigen::OuterStride<>(ld));
  s.noalias() -= Eigen::Map<const Eigen::Matrix<double, R, K>>(A).lazyProduct(
      Eigen::Map<const Eigen::Matrix<double, C, K>>(B).transpose());
}

template <int K>
bool subtractK(double* S, int ld, int r, int c, const double* A, const double* B) {
  if (r == 6 && c == 6) return subtractFixed<6, 6, K>(S, ld, A, B), true;
  if (r == 6 && c == 3) return subtractFixed<6, 3, K>(S, ld, A, B), true;
  if (r == 3 && c == 6) return subtractFixed<3, 6, K>(S, ld, A, B), true;
  if (r == 3 && c == 3) return subtractFixed<3, 3, K>(S, ld, A, B), true;
  return false;
}

void subtractProduct(Eigen::MatrixXd* S, int oi, int oj, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const int r = static_cast<int>(A.rows()), c = static_cast<int>(B.rows()), k = static_cast<int>(A.cols());
  double* s = S->data() + oi + static_cast<std::ptrdiff_t>(oj) * S->rows();
  const int ld = static_cast<int>(S->rows());
  if (k == 6 && subtractK<6>(s, ld, r, c, A.data(), B.data())) return;
  if (k == 3 && subtractK<3>(s, ld, r, c, A.data(), B.data())) return;
  S->block(oi, oj, r, c).noalias() -= A.lazyProduct(B.transpose());
}

}  // namespace

bool BlockSparseCholesky::factorize(Eigen::MatrixXd* S, const std::vector<int>& offsets,
                                    const std::vector<int>& sizes) {
  offsets_ = offsets;
  sizes_ = sizes;
  const int nb = static_cast<int>(offsets.size());
  // Symbolic: the block pattern, then minimum degree (in scalar columns) with fill. Within one
  // solve the pattern repeats from step to step, so the order is kept while it does.
  std::vector<char> pattern(static_cast<std::size_t>(nb) * nb, 0);
  for (int i = 0; i < nb; ++i)
    for (int j = i + 1; j < nb; ++j)
      if ((S->block(offsets[i], offsets[j], sizes[i], sizes[j]).array() != 0.0).any())
        pattern[i * nb + j] = pattern[j * nb + i] = 1;
  if (pattern != pattern_ || steps_.size() != static_cast<std::size_t>(nb)) {
    pattern_ = pattern;
    std::vector<char> adjacent = pattern, done(nb, 0);
    steps_.assign(nb, Step());
    for (int k = 0; k < nb; ++k) {
      int best = -1;
      long best_degree = std::numeric_limits<long>::max();
      for (int i = 0; i < nb; ++i) {
        if (done[i]) continue;
        long degree = 0;
        for (int j = 0; j < nb; ++j)
          if (!done[j] && adjacent[i * nb + j]) degree += sizes[j];
        if (degree < best_degree) {
          best_degree = degree;
          best = i;
        }
      }
      Step& step = steps_[k];
      step.block = best;
      for (int j = 0; j < nb; ++j)
        if (!done[j] && adjacent[best * nb + j]) step.later.push_back(j);
      for (int a : step.later)
        for (int b : step.later)
          if (a != b) adjacent[a * nb + b] = 1;  // fill
      done[best] = 1;
    }
  }
  // Numeric, right-looking: factor the pivot, then update the blocks it couples.
  for (Step& step : steps_) {
    const int p = step.block, op = offsets[p], sp = sizes[p];
    const Eigen::MatrixXd pivot = S->block(op, op, sp, sp).selfadjointView<Eigen::Upper>();
    const Eigen::LLT<Eigen::MatrixXd> llt(pivot);
    if (llt.info() != Eigen::Success) return false;
    step.L_diag = llt.matrixL();
    step.L_later.resize(step.later.size());
    // L_ip = S_ip L_pp^-T, with L_pp^-1 formed once per pivot (a 3x3 or 6x6 block).
    const Eigen::MatrixXd L_inv_t =
        step.L_diag.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(sp, sp)).transpose();
    for (std::size_t a = 0; a < step.later.size(); ++a) {
      const int i = step.later[a];
      step.L_later[a].noalias() = blockOf(*S, offsets[i], sizes[i], op, sp).lazyProduct(L_inv_t);
    }
    for (std::size_t a = 0; a < step.later.size(); ++a) {
      const int i = step.later[a];
      for (std::size_t b = 0; b < step.later.size(); ++b) {
        const int j = step.later[b];
        if (offsets[i] > offsets[j]) continue;  // the upper triangle (and full diagonal blocks)
        subtractProduct(S, offsets[i], offsets[j], step.L_later[a], step.L_later[b]);
      }
    }
  }
  return true;
}

void BlockSparseCholesky::solve(Eigen::VectorXd* b) const {
  Eigen::VectorXd& x = *b;
  for (const Step& step : steps_) {  // L y = b
    auto yp = x.segment(offsets_[step.block], sizes_[step.block]);
    step.L_diag.triangularView<Eigen::Lower>().solveInPlace(yp);
    for (std::size_t a = 0; a < step.later.size(); ++a)
      x.segment(offsets_[step.later[a]], sizes_[step.later[a]]).noalias() -= step.L_later[a] * yp;
  }
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it) {  // L^T x = y
    const Step& step = *it;
    Eigen::VectorXd yp = x.segment(offsets_[step.block], sizes_[step.block]);
    for (std::size_t a = 0; a < step.later.size(); ++a)
      yp.noalias() -= step.L_later[a].transpose() * x.segment(offsets_[step.later[a]], sizes_[step.later[a]]);
    step.L_diag.transpose().triangularView<Eigen::Upper>().solveInPlace(yp);
    x.segment(offsets_[step.block], sizes_[step.block]) = yp;
  }
}

}  // namespace hdvio
