// The landmark kernel of the own solver's Schur complement (core/src/schur_lm_blocks.h): the
// column-wise product gives the same bits as the coefficient-wise one it replaces, so a solve
// is byte-identical with either, and it touches only its block.
#include <gtest/gtest.h>

#include <random>

#include "schur_lm_blocks.h"

namespace hdvio {
namespace {

template <int R, int C>
void expectSameBitsAsCoefficientProduct(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Eigen::MatrixXd S(14, 15);
  for (Eigen::Index k = 0; k < S.size(); ++k) S.data()[k] = u(rng);
  double V[R * 3], W[C * 3], Vt[R * 3];
  for (double& x : V) x = u(rng) * 1e3;  // spread exponents so that rounding order shows
  for (double& x : W) x = u(rng) * 1e-2;
  for (int r = 0; r < R; ++r)
    for (int k = 0; k < 3; ++k) Vt[k * R + r] = V[r * 3 + k];
  const int i = 5, j = 7;
  Eigen::MatrixXd expected = S, actual = S;
  schur_lm_blocks::subtractFixed<R, C, 3>(&expected, i, j, V, W);
  schur_lm_blocks::subtractColumns3<R, C>(actual.data() + i + j * actual.rows(), actual.rows(), Vt, W);
  for (Eigen::Index c = 0; c < S.cols(); ++c)
    for (Eigen::Index r = 0; r < S.rows(); ++r) {
      EXPECT_EQ(actual(r, c), expected(r, c)) << R << "x" << C << " at " << r << ", " << c;
      const bool inside = r >= i && r < i + R && c >= j && c < j + C;
      if (!inside) {
        EXPECT_EQ(actual(r, c), S(r, c));
      }
    }
  EXPECT_GT((actual - S).cwiseAbs().maxCoeff(), 1.0);
}

TEST(SchurLmBlocks, ColumnKernelGivesTheCoefficientProductsBits) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    expectSameBitsAsCoefficientProduct<6, 6>(seed);
    expectSameBitsAsCoefficientProduct<6, 3>(seed);
    expectSameBitsAsCoefficientProduct<3, 6>(seed);
    expectSameBitsAsCoefficientProduct<3, 3>(seed);
  }
}

}  // namespace
}  // namespace hdvio
