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
  linkEntries(dataset, partial, {"mav0"});
  linkEntries(fs::path(dataset) / "mav0", partial / "mav0", {"cam0"});
  linkEntries(cam, partial / "mav0" / "cam0", {"data"});
  const fs::path data = partial / "mav0" / "cam0" / "data";
  fs::create_directories(data);
  const fs::path original_data = fs::canonical(cam / "data");
  for (const ImageRef& ref : seq.images) {
    const cv::Mat pixels = io::loadImage(ref, &*seq.camera);  // InputError names the csv row
    const fs::path rel = fs::canonical(ref.path).lexically_relative(original_data);
    if (rel.empty() || *rel.begin() == "..")
      throw InputError(ref.list_file, ref.list_line, "image outside cam0/data: " + ref.path);
    fs::create_directories((data / rel).parent_path());
    const fs::path png = fs::path(data / rel).replace_extension(".png");
    if (png != data / rel)
      throw InputError(ref.list_file, ref.list_line, "only PNG images can be copied: " + ref.path);
    if (!cv::imwrite(png.string(), withImageNoise(pixels, sigma, seed, ref.t)))
      throw InputError(png.string(), 0, "cannot write the image");
  }
  fs::rename(partial, out);
}

}  // namespace hdvio::run
