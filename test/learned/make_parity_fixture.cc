// Writes data/tcn_parity_reference.txt: libtorch's outputs for the deterministic TCN and
// inputs of deterministic_tcn.h. Built only with HDVIO_WITH_TORCH; rerun after changing them:
//   test/learned/hdvio_make_tcn_parity_fixture > test/learned/data/tcn_parity_reference.txt
//   test/learned/hdvio_make_tcn_parity_fixture residual > test/learned/data/tcn_residual_parity_reference.txt
#include <cstdio>
#include <cstring>

#include "deterministic_tcn.h"
#include "hdvio/learned/torch/tcn_module.h"

int main(int argc, char** argv) {
  using namespace hdvio::learned;
  const bool residual = argc > 1 && std::strcmp(argv[1], "residual") == 0;
  const Tcn tcn = residual ? testing::deterministicResidualTcn() : testing::deterministicTcn();
  TcnModule module = importTcn(tcn);
  module->eval();
  torch::NoGradGuard no_grad;
  const MatrixXf x =
      testing::deterministicInputs(residual ? testing::kResidualParitySteps : testing::kParitySteps);
  torch::Tensor in = torch::empty({1, 6, x.cols()}, torch::kFloat32);
  for (long c = 0; c < 6; ++c)
    for (long t = 0; t < x.cols(); ++t) in[0][c][t] = x(c, t);
  const torch::Tensor out = module->forward(in)[0].contiguous();  // 6 x T
  std::printf("# libtorch %s float32 outputs of the deterministic %sTCN (test/learned/deterministic_tcn.h)\n",
              TORCH_VERSION, residual ? "residual " : "");
  std::printf(residual ? "# one line per time step: displacement x y z\n"
                       : "# one line per time step: force x y z, log-variance x y z\n");
  for (long t = 0; t < out.size(1); ++t) {
    for (long c = 0; c < out.size(0); ++c) std::printf(c ? " %.9g" : "%.9g", out[c][t].item<float>());
    std::printf("\n");
  }
  return 0;
}
