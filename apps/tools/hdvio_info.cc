// hdvio_info [--check] <path>: what a dataset holds and which methods it can serve. Images load
// lazily, so only --check decodes them all (and compares their size with the calibration); it
// stops at the first bad one with one error line and exit code 2, before printing anything.
#include <gflags/gflags.h>

#include <cstdio>
#include <exception>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/image.h"
#include "hdvio/io/sequence_info.h"
#include "hdvio/io/sequence_reader.h"

DEFINE_string(topics, "", "ROS bags: topic-map YAML (default: EuRoC topics, docs/datasets.md)");
DEFINE_string(calibration, "", "ROS bags: folder with cam0/ and imu0/sensor.yaml (an ASL mav0), or Kalibr files camchain.yaml,imu.yaml");
DEFINE_double(max_imu_gap_s, 0.05, "Largest allowed spacing of IMU samples [s]");
DEFINE_double(thrust_coefficient, 0.0, "Rotor thrust coefficient [N s^2 rad^-2] for rotor-speed datasets (0: none)");
DEFINE_double(mass, 0.0, "Vehicle mass [kg] overriding the dataset's (0: dataset default)");
DEFINE_bool(check, false, "Also decode every image and check its size against the camera calibration");

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_info [--check] <path> [--topics <yaml>] [--calibration <dir>]\n"
      "what a dataset holds and which methods it can serve; path: ASL folder, Blackbird or DIDO\n"
      "folder / data.hdf5, NeuroBEM .csv, ROS 1 bag (with --calibration)\n"
      "example: hdvio_info --check ../shared/data/euroc/V1_01_easy_excerpt");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {}, argc == 2)) return bad;
  return hdvio::runTool([&] {
    hdvio::io::ReadOptions options;
    options.max_imu_gap_s = FLAGS_max_imu_gap_s;
    if (FLAGS_thrust_coefficient > 0.0) options.thrust_coefficient = FLAGS_thrust_coefficient;
    if (FLAGS_mass > 0.0) options.mass = FLAGS_mass;
    options.bag_topics = FLAGS_topics;
    options.calibration = FLAGS_calibration;
    const hdvio::io::DatasetFormat format = hdvio::io::detectFormat(argv[1]);
    const hdvio::Sequence seq = hdvio::io::readSequence(argv[1], options);
    const std::size_t checked = FLAGS_check ? hdvio::io::checkAllImages(seq) : 0;
    std::printf("format:   %s\n%s", hdvio::io::formatName(format),
                hdvio::io::formatSummary(hdvio::io::summarize(seq)).c_str());
    if (FLAGS_check && seq.camera)
      std::printf("check:    %zu images decoded, all %dx%d 8-bit as %s says\n", checked, seq.camera->width,
                  seq.camera->height, seq.camera->file.c_str());
    else if (FLAGS_check)
      std::printf("check:    no camera, no images to check\n");
    return 0;
  });
}
