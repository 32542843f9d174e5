#include "hdvio/run/noisy_image_copy.h"

#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/pipeline/visual_sequence_runner.h"

namespace hdvio::run {
namespace fs = std::filesystem;

namespace {
// Links every entry of `from` into `to`, except the names in `skip`.
void linkEntries(const fs::path& from, const fs::path& to, const std::vector<std::string>& skip) {
  fs::create_directories(to);
  for (const fs::directory_entry& e : fs::directory_iterator(from)) {
    const std::string name = e.path().filename().string();
    bool skipped = false;
    for (const std::string& s : skip) skipped = skipped || name == s;
    if (!skipped) fs::create_symlink(fs::absolute(e.path()), to / name);
  }
}

// The copy's files under `partial`: links, and the images with the seed's noise. Image paths are
// compared lexically (not through symbolic links: a folder of linked images is a valid source).
void writeInto(const std::string& dataset, const fs::path& cam, const CameraCalibration& camera,
               const std::vector<ImageRef>& images, double sigma, std::uint32_t seed,
               const fs::path& partial) {
  linkEntries(dataset, partial, {"mav0"});
  linkEntries(fs::path(dataset) / "mav0", partial / "mav0", {"cam0"});
  linkEntries(cam, partial / "mav0" / "cam0", {"data"});
  const fs::path data = partial / "mav0" / "cam0" / "data";
  fs::create_directories(data);
  const fs::path original_data = fs::absolute(cam / "data").lexically_normal();
  for (const ImageRef& ref : images) {
    const cv::Mat pixels = io::loadImage(ref, &camera);  // InputError names the csv row
    const fs::path rel = fs::absolute(ref.path).lexically_normal().lexically_relative(original_data);
    if (rel.empty() || *rel.begin() == "..")
      throw InputError(ref.list_file, ref.list_line, "image outside cam0/data: " + ref.path);
    if (rel.extension() != ".png")
      throw InputError(ref.list_file, ref.list_line, "only PNG images can be copied: " + ref.path);
    fs::create_directories((data / rel).parent_path());
    if (!cv::imwrite((data / rel).string(), withImageNoise(pixels, sigma, seed, ref.t)))
      throw InputError((data / rel).string(), 0, "cannot write the image");
  }
}
}  // namespace

void writeNoisyImageCopy(const std::string& dataset, double sigma, std::uint32_t seed,
                         const std::string& out) {
  if (!(sigma > 0.0)) throw InputError("--sigma", 0, "must be positive");
  std::error_code ec;
  if (fs::exists(out, ec)) throw InputError(out, 0, "output folder exists; not overwritten");
  const fs::path cam = fs::path(dataset) / "mav0" / "cam0";
  if (!fs::is_directory(cam / "data", ec))
    throw InputError(dataset, 0, "not an ASL folder with images (no mav0/cam0/data)");
  const Sequence seq = io::readAsl(dataset);
  if (!seq.hasImages()) throw InputError(dataset, 0, "the sequence lists no cam0 images");

  const fs::path partial = fs::path(out).string() + ".partial";
  fs::remove_all(partial, ec);
  try {
    writeInto(dataset, cam, *seq.camera, seq.images, sigma, seed, partial);
  } catch (...) {  // no half-written copy is left behind
    fs::remove_all(partial, ec);
    throw;
  }
  fs::rename(partial, out);
}

}  // namespace hdvio::run
