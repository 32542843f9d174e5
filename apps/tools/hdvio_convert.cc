// hdvio_convert --input <dataset> --output <asl folder>: any supported dataset to the ASL layout.
#include <gflags/gflags.h>

#include <cstdio>
#include <exception>
#include <filesystem>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/sequence_reader.h"

DEFINE_string(input, "", "Blackbird / DIDO folder or data.hdf5, NeuroBEM .csv, ROS bag, or ASL folder");
DEFINE_string(topics, "", "ROS bags: topic-map YAML (default: EuRoC topics, docs/datasets.md)");
DEFINE_string(calibration, "", "ROS bags: folder with cam0/ and imu0/sensor.yaml (an ASL mav0), or Kalibr files camchain.yaml,imu.yaml");

DEFINE_string(output, "", "Output ASL folder (must be empty or absent unless --force)");
DEFINE_bool(force, false, "Replace an existing ASL output folder (one holding only mav0/)");
DEFINE_double(max_imu_gap_s, 0.05, "Largest allowed spacing of IMU samples [s]");
DEFINE_double(thrust_coefficient, 0.0, "Rotor thrust coefficient [N s^2 rad^-2] written to rotor0/sensor.yaml (0: none)");
DEFINE_double(mass, 0.0, "Vehicle mass [kg] (0: dataset default)");

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_convert --input <dataset path> [--topics <yaml>] [--calibration <dir>] --output <asl folder> [--force]\n"
      "converts any supported dataset (ROS 1 bags included) to the ASL folder layout\n"
      "example: hdvio_convert --input flight.bag --calibration ../shared/data/euroc/V1_01_easy_excerpt/mav0 --output /tmp/asl");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_input, FLAGS_output}, argc == 1)) return bad;
  return hdvio::runTool([&] {
    const fs::path out = fs::absolute(FLAGS_output).lexically_normal();
    const bool non_empty = fs::exists(out) && (!fs::is_directory(out) || !fs::is_empty(out));
    if (non_empty && !FLAGS_force)
      throw hdvio::InputError(FLAGS_output, 0, "output exists and is not empty (use --force to replace it)");
    if (non_empty) {
      // --force replaces a previous conversion, never an arbitrary folder.
      bool only_mav0 = fs::is_directory(out);
      if (only_mav0) {
        for (const auto& entry : fs::directory_iterator(out)) only_mav0 = only_mav0 && entry.path().filename() == "mav0";
      }
      if (!only_mav0)
        throw hdvio::InputError(FLAGS_output, 0, "--force only replaces an ASL folder that holds nothing but mav0/");
    }
    const fs::path in = fs::weakly_canonical(fs::absolute(FLAGS_input));
    const std::string in_s = in.string(), out_s = fs::weakly_canonical(out).string();
    if (in_s == out_s || in_s.rfind(out_s + "/", 0) == 0)
      throw hdvio::InputError(FLAGS_output, 0, "output must not contain the input");

    hdvio::io::ReadOptions options;
    options.max_imu_gap_s = FLAGS_max_imu_gap_s;
    if (FLAGS_thrust_coefficient > 0.0) options.thrust_coefficient = FLAGS_thrust_coefficient;
    if (FLAGS_mass > 0.0) options.mass = FLAGS_mass;
    options.bag_topics = FLAGS_topics;
    options.calibration = FLAGS_calibration;
    const hdvio::Sequence seq = hdvio::io::readSequence(FLAGS_input, options);  // fully validated first
    if (non_empty) fs::remove_all(out / "mav0");
    hdvio::io::writeAsl(seq, out.string());
    std::printf("wrote %s (%zu IMU, %zu thrust, %zu rotor, %zu images, %zu ground-truth samples)\n",
                out.string().c_str(), seq.imu.size(), seq.thrust.size(), seq.rotor.size(),
                seq.images.size(), seq.groundtruth.size());
    for (const auto& w : seq.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return 0;
  });
}
