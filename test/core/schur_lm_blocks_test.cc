// The landmark kernels of the own solver's Schur complement (core/src/schur_lm_blocks.h): the
// column-wise product gives the same bits as the coefficient-wise one it replaces, and the
// fixed-size V and right-hand side the same as the dynamic-size products, so a solve is
// byte-identical with either; the block kernel touches only its block.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "schur_lm_blocks.h"

namespace hdvio {
namespace {

// The coefficient-wise product the column kernel replaced, as it was.
template <int R, int C>
void subtractCoefficientWise(Eigen::MatrixXd* S, int i, int j, const double* V, const double* W) {
  Eigen::Map<const Eigen::Matrix<double, R, 3, Eigen::RowMajor>> v(V);
  Eigen::Map<const Eigen::Matrix<double, C, 3, Eigen::RowMajor>> w(W);
  S->block<R, C>(i, j).noalias() -= v.lazyProduct(w.transpose());
}

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
  subtractCoefficientWise<R, C>(&expected, i, j, V, W);
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

// The fixed-size V = W A^-1 and rhs += V g of a landmark against the dynamic-size products.
template <int R>
void expectLandmarkVSameBits(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Eigen::MatrixXd A_inv(3, 3);
  Eigen::VectorXd g(3), rhs_expected(R), rhs_actual(R);
  double W[R * 3], V_expected[R * 3], V_actual[R * 3];
  for (Eigen::Index k = 0; k < 9; ++k) A_inv.data()[k] = u(rng) * 1e-3;
  for (Eigen::Index k = 0; k < 3; ++k) g(k) = u(rng) * 1e2;
  for (double& x : W) x = u(rng) * 1e4;
  for (Eigen::Index k = 0; k < R; ++k) rhs_expected(k) = rhs_actual(k) = u(rng);
  schur_lm_blocks::RowMap Ve(V_expected, R, 3);
  Ve.noalias() = schur_lm_blocks::ConstRowMap(W, R, 3).lazyProduct(A_inv);
  rhs_expected.noalias() += Ve.lazyProduct(g);
  schur_lm_blocks::landmarkV<R>(W, A_inv.data(), g.data(), V_actual, rhs_actual.data());
  for (int k = 0; k < R * 3; ++k) EXPECT_EQ(V_actual[k], V_expected[k]) << R << " V " << k;
  for (int k = 0; k < R; ++k) EXPECT_EQ(rhs_actual(k), rhs_expected(k)) << R << " rhs " << k;
}

TEST(SchurLmBlocks, FixedSizeLandmarkProductsGiveTheDynamicOnesBits) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    expectLandmarkVSameBits<6>(seed);
    expectLandmarkVSameBits<3>(seed);
  }
}

// W = Jc^T Ja written directly gives the bits of the former zero fill followed by addJtJ.
template <int TC, int TA>
void expectSetJtJSameBits(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  double Jc[2 * TC], Ja[2 * TA], expected[TC * TA], actual[TC * TA];
  for (double& x : Jc) x = u(rng) * 1e3;
  for (double& x : Ja) x = u(rng) * 1e-2;
  for (int k = 0; k < TC * TA; ++k) {
    expected[k] = 0.0;
    actual[k] = std::numeric_limits<double>::quiet_NaN();  // must be overwritten, not added to
  }
  schur_lm_blocks::addJtJ(expected, TC, 2, TC, TA, Jc, Ja);
  schur_lm_blocks::setJtJ(actual, 2, TC, TA, Jc, Ja);
  for (int k = 0; k < TC * TA; ++k) EXPECT_EQ(actual[k], expected[k]) << TC << "x" << TA << " " << k;
}

TEST(SchurLmBlocks, WrittenLandmarkPoseBlockGivesTheAccumulatedOnesBits) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    expectSetJtJSameBits<3, 6>(seed);
    expectSetJtJSameBits<3, 3>(seed);
    expectSetJtJSameBits<6, 6>(seed);  // the dynamic-size fallback
  }
}

// Random entries over four decades, so that the order of a sum shows in its rounding.
void fillSpread(std::mt19937* rng, double* x, int n) {
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int k = 0; k < n; ++k) x[k] = u(*rng) * std::pow(10.0, static_cast<int>(u(*rng)));
}

// An in-place kernel against Eigen's dynamic-size product: the same bits where Eigen sums with
// two-double packets (the project's SSE2 / NEON builds), else within round-off.
void expectSameAsDynamic(const double* actual, const Eigen::VectorXd& expected, int size) {
  constexpr bool kPacketsOfTwo = Eigen::internal::packet_traits<double>::size == 2;
  for (int k = 0; k < expected.size(); ++k) {
    if (kPacketsOfTwo) {
      EXPECT_EQ(actual[k], expected(k)) << "block size " << size << ", entry " << k;
    } else {
      EXPECT_NEAR(actual[k], expected(k), 1e-12 * (1.0 + std::abs(expected(k))));
    }
  }
}

// J dx of a reprojection's blocks in the model cost change.
TEST(SchurLmBlocks, TwoRowProductGivesTheDynamicProductsBits) {
  std::mt19937 rng(7);
  for (int cols : {3, 6}) {
    for (int trial = 0; trial < 2000; ++trial) {
      double J[12], dx[6], actual[2];
      fillSpread(&rng, J, 12);
      fillSpread(&rng, dx, 6);
      fillSpread(&rng, actual, 2);
      Eigen::VectorXd expected = Eigen::Map<Eigen::Vector2d>(actual);
      expected.noalias() += schur_lm_blocks::ConstRowMap(J, 2, cols) * schur_lm_blocks::ConstVecMap(dx, cols);
      ASSERT_TRUE(schur_lm_blocks::addTwoRowProduct(actual, J, cols, dx));
      expectSameAsDynamic(actual, expected, cols);
    }
  }
  double J[8] = {0}, dx[4] = {0}, jd[2] = {1.0, 2.0};
  EXPECT_FALSE(schur_lm_blocks::addTwoRowProduct(jd, J, 4, dx));
  EXPECT_EQ(jd[1], 2.0);
}

// A landmark's t -= W^T d in the back substitution.
TEST(SchurLmBlocks, LandmarkBackSubstitutionGivesTheDynamicProductsBits) {
  std::mt19937 rng(11);
  for (int rows : {3, 6}) {
    for (int trial = 0; trial < 2000; ++trial) {
      double W[18], d[6], actual[3];
      fillSpread(&rng, W, 18);
      fillSpread(&rng, d, 6);
      fillSpread(&rng, actual, 3);
      Eigen::VectorXd expected = Eigen::Map<Eigen::Vector3d>(actual);
      expected.noalias() -= schur_lm_blocks::ConstRowMap(W, rows, 3).transpose() *
                            schur_lm_blocks::ConstVecMap(d, rows);
      ASSERT_TRUE(schur_lm_blocks::subtractLandmarkWtd(actual, W, rows, d));
      expectSameAsDynamic(actual, expected, rows);
    }
  }
  double W[12] = {0}, d[4] = {0}, t[3] = {1.0, 2.0, 3.0};
  EXPECT_FALSE(schur_lm_blocks::subtractLandmarkWtd(t, W, 4, d));
  EXPECT_EQ(t[2], 3.0);
}

}  // namespace
}  // namespace hdvio
