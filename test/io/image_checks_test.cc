// loadImage checks what it decodes: missing, empty, truncated, corrupt, non-8-bit or wrongly
// sized images are InputErrors naming the camera file and the row that lists the image.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

#include "hdvio/core/error.h"
#include "hdvio/io/image.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

class ImageChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    camera_.width = 64;
    camera_.height = 48;
    camera_.file = dir_ / "cam0/sensor.yaml";
  }
  // A noisy image: compresses badly, so a cut file loses real pixel data.
  static cv::Mat noise(int width, int height, int type = CV_8UC1) {
    cv::Mat m(height, width, type);
    cv::randu(m, 0, type == CV_16UC1 ? 65535 : 255);
    return m;
  }
  ImageRef write(const std::string& name, const cv::Mat& pixels) {
    ImageRef ref{7, dir_ / name, std::nullopt, dir_ / "cam0/data.csv", 12};
    EXPECT_TRUE(cv::imwrite(ref.path, pixels));
    return ref;
  }
  static std::vector<char> bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  static void overwrite(const std::string& path, const std::vector<char>& b) {
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(b.data(), static_cast<long>(b.size()));
  }
  // The error is reported at the camera file's row and names the image and the problem.
  void expectError(const ImageRef& ref, const std::string& fragment) {
    try {
      loadImage(ref, &camera_);
      ADD_FAILURE() << "no error for " << ref.path << ", expected " << fragment;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), ref.list_file);
      EXPECT_EQ(e.line(), 12);
      EXPECT_NE(e.problem().find("image " + ref.path + ": "), std::string::npos) << e.what();
      EXPECT_NE(e.problem().find(fragment), std::string::npos) << e.what();
    }
  }
  test::TempDir dir_{"image_checks"};
  CameraCalibration camera_;
};

TEST_F(ImageChecks, GoodImagesLoadAsGray8) {
  const cv::Mat gray = noise(64, 48);
  const cv::Mat loaded = loadImage(write("a.png", gray), &camera_);
  ASSERT_EQ(loaded.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(loaded, gray, cv::NORM_INF), 0.0);
  EXPECT_EQ(loadImage(write("c.png", noise(64, 48, CV_8UC3)), &camera_).type(), CV_8UC1);
  EXPECT_EQ(loadImage(write("d.jpg", gray), &camera_).size(), cv::Size(64, 48));
  EXPECT_EQ(loadImage(write("e.png", noise(10, 10))).size(), cv::Size(10, 10));  // no camera: any size
}

TEST_F(ImageChecks, SizeMustMatchTheCalibration) {
  expectError(write("small.png", noise(40, 48)), "image is 40x48 but " + camera_.file + " says 64x48");
  expectError(write("tall.png", noise(64, 50)), "image is 64x50");
}

TEST_F(ImageChecks, TruncatedAndCorruptPngAreDetected) {
  const ImageRef ref = write("cut.png", noise(64, 48));
  const std::vector<char> full = bytes(ref.path);
  overwrite(ref.path, std::vector<char>(full.begin(), full.begin() + full.size() * 6 / 10));
  expectError(ref, "truncated PNG");
  overwrite(ref.path, std::vector<char>(full.begin(), full.end() - 12));  // only IEND missing
  expectError(ref, "truncated PNG (no IEND chunk)");
  std::vector<char> flipped = full;
  flipped[full.size() / 2] ^= 0x5A;  // inside the image data
  overwrite(ref.path, flipped);
  expectError(ref, "corrupt PNG (CRC mismatch in IDAT");
}

TEST_F(ImageChecks, EmptyMissingNonImageAndSixteenBitFiles) {
  const ImageRef empty = write("empty.png", noise(64, 48));
  overwrite(empty.path, {});
  expectError(empty, "image file is empty (0 bytes)");
  ImageRef missing = empty;
  missing.path = dir_ / "nope.png";
  expectError(missing, "cannot open image file");
  const ImageRef text = write("text.png", noise(64, 48));
  overwrite(text.path, {'h', 'e', 'l', 'l', 'o'});
  expectError(text, "cannot decode image");
  expectError(write("deep.png", noise(64, 48, CV_16UC1)), "expected an 8-bit image, found 16-bit");
  const ImageRef jpg = write("cut.jpg", noise(64, 48));
  const std::vector<char> j = bytes(jpg.path);
  overwrite(jpg.path, std::vector<char>(j.begin(), j.begin() + j.size() / 2));
  expectError(jpg, "truncated JPEG");
}

TEST_F(ImageChecks, WithoutACameraFileTheImageIsNamed) {
  ImageRef ref = write("small.png", noise(40, 48));
  ref.list_file.clear();
  try {
    loadImage(ref, &camera_);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), ref.path);
    EXPECT_EQ(e.line(), 0);
  }
}

TEST_F(ImageChecks, CheckAllImagesStopsAtTheFirstBadOne) {
  Sequence seq;
  seq.camera = camera_;
  for (int i = 0; i < 3; ++i) seq.images.push_back(write("f" + std::to_string(i) + ".png", noise(64, 48)));
  EXPECT_EQ(checkAllImages(seq), 3u);
  seq.images[1] = write("bad.png", noise(32, 48));
  EXPECT_THROW(checkAllImages(seq), InputError);
}

}  // namespace
}  // namespace hdvio::io
