#pragma once
// libtorch picks its CPU kernels by the machine's instruction set: oneDNN (the convolutions)
// runs AVX-512 code where the CPU has it and AVX2 code elsewhere, and the two round
// differently, so the same training command wrote different weights on two machines (the demo's
// hdvio row: 0.2293 m with AVX2 kernels, 0.2481 m with AVX-512, docs/learned.md). Training
// pins the kernels to AVX2 (oneDNN's DNNL_MAX_CPU_ISA, ATen's ATEN_CPU_CAPABILITY) so the weights
// are the same on every machine with AVX2. A value already in the environment is kept (set
// them to compare, or on a CPU without AVX2). Call before the first libtorch operation.
namespace hdvio::learned {

void pinReproducibleCpuKernels();

}  // namespace hdvio::learned
