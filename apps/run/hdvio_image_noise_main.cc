// hdvio_image_noise: an ASL folder whose cam0 images carry hdvio's seeded image noise, for a peer
// estimator to see the pixels `run: {image_noise_sigma: s, seed: k}` gives hdvio_run.
//   hdvio_image_noise --dataset <ASL> --sigma 1 --seed 2 --out <new folder>
#include <gflags/gflags.h>

#include <cstdio>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/run/noisy_image_copy.h"

DEFINE_string(dataset, "", "ASL folder with cam0 images");
DEFINE_double(sigma, 0.0, "noise standard deviation in gray levels (run.image_noise_sigma)");
DEFINE_int32(seed, 1, "noise seed (run.seed)");
DEFINE_string(out, "", "output folder (must not exist; images written, other files linked)");

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_image_noise --dataset <ASL folder> --sigma <gray levels> --seed <k> --out <folder>\n"
      "writes a copy of an ASL folder whose cam0 images carry the noise hdvio_run adds with\n"
      "run: {image_noise_sigma: sigma, seed: k} (other files are symbolic links), for peers\n"
      "example: hdvio_image_noise --dataset /tmp/sim_tiny --sigma 1 --seed 1 --out /tmp/sim_tiny_n1");
  return hdvio::runTool([] {
    if (FLAGS_dataset.empty() || FLAGS_out.empty())
      throw hdvio::InputError("", 0, "usage: hdvio_image_noise --dataset <ASL> --sigma <s> --seed <k> --out <dir>");
    if (FLAGS_seed < 0) throw hdvio::InputError("--seed", 0, "must be non-negative");
    hdvio::run::writeNoisyImageCopy(FLAGS_dataset, FLAGS_sigma,
                                    static_cast<std::uint32_t>(FLAGS_seed), FLAGS_out);
    std::fprintf(stderr, "hdvio_image_noise: wrote %s\n", FLAGS_out.c_str());
    return 0;
  });
}
