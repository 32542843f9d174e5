#pragma once
// Cholesky of a symmetric positive definite matrix made of variable-sized blocks, most of them
// zero (a sliding window's reduced camera system: velocities and biases couple neighbouring
// frames only, poses are dense among themselves). The blocks are eliminated in minimum-degree
// order (ties by block index, so the order is a function of the pattern alone) and only the
// non-zero blocks and their fill are computed; a dense Cholesky of the same 240 x 240 window
// system costs several times more.
#include <vector>

#include <Eigen/Core>

namespace hdvio {

class BlockSparseCholesky {
 public:
  // S: dense storage, only its upper triangle (and full diagonal blocks) is read; it is
  // overwritten. offsets / sizes: the blocks, contiguous and covering S. false if a pivot
  // block is not positive definite.
  bool factorize(Eigen::MatrixXd* S, const std::vector<int>& offsets, const std::vector<int>& sizes);
  // Solves S x = b in place with the last factorization. The elimination order is recomputed
  // only when the block pattern changes (the object can serve the steps of one solve).
  void solve(Eigen::VectorXd* b) const;

 private:
  struct Step {
    int block = 0;
    std::vector<int> later;                 // blocks not yet eliminated that couple to it
    std::vector<Eigen::MatrixXd> L_later;   // L(later[i], block)
    Eigen::MatrixXd L_diag;                 // lower-triangular factor of the pivot block
  };
  std::vector<Step> steps_;
  std::vector<int> offsets_, sizes_;
  std::vector<char> pattern_;  // block pattern of the last factorization (nb x nb)
};

}  // namespace hdvio
