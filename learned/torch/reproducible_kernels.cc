#include "hdvio/learned/torch/reproducible_kernels.h"

#include <cstdlib>

namespace hdvio::learned {

void pinReproducibleCpuKernels() {
  // Both libraries read the variable once, at their first dispatch; overwrite = 0 keeps a
  // user's choice.
  setenv("DNNL_MAX_CPU_ISA", "AVX2", 0);
  setenv("ATEN_CPU_CAPABILITY", "avx2", 0);
}

}  // namespace hdvio::learned
