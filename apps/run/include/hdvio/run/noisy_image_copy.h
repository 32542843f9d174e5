#pragma once
// A copy of an ASL folder whose cam0 images carry the noise that `run.image_noise_sigma: sigma`
// with `run.seed: seed` adds to the decoded images (withImageNoise), written as PNG (lossless),
// so that an external estimator (a peer such as OpenVINS) sees the very pixels hdvio's seeded
// run sees. Every other file is a symbolic link into the original folder.
#include <cstdint>
#include <string>

namespace hdvio::run {

// Writes the copy to `out` (through `<out>.partial`, renamed when complete). InputError when the
// dataset is not an ASL folder with cam0 images, an image does not decode or does not match
// cam0/sensor.yaml (file and line of its cam0/data.csv row), or `out` already exists.
void writeNoisyImageCopy(const std::string& dataset, double sigma, std::uint32_t seed,
                         const std::string& out);

}  // namespace hdvio::run
