// hdvio_info <path>: what a dataset holds and which methods it can serve.
#include <gflags/gflags.h>

#include <cstdio>
#include <exception>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/sequence_info.h"
#include "hdvio/io/sequence_reader.h"

DEFINE_string(topics, "", "ROS bags: topic-map YAML (default: EuRoC topics, docs/datasets.md)");
DEFINE_string(calibration, "", "ROS bags: folder with cam0/sensor.yaml and imu0/sensor.yaml (e.g. an ASL mav0)");
DEFINE_double(max_imu_gap_s, 0.05, "Largest allowed spacing of IMU samples [s]");
DEFINE_double(thrust_coefficient, 0.0, "Rotor thrust coefficient [N s^2 rad^-2] for rotor-speed datasets (0: none)");
DEFINE_double(mass, 0.0, "Vehicle mass [kg] overriding the dataset's (0: dataset default)");

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "hdvio_info <path> [--topics <yaml>] [--calibration <dir>]\n"
      "  path: ASL folder, Blackbird or DIDO folder / data.hdf5, NeuroBEM .csv, ROS bag");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  if (argc != 2) {
    std::fprintf(stderr, "%s\n", gflags::ProgramUsage());
    return hdvio::kExitBadInput;
  }
  return hdvio::runTool([&] {
    hdvio::io::ReadOptions options;
    options.max_imu_gap_s = FLAGS_max_imu_gap_s;
    if (FLAGS_thrust_coefficient > 0.0) options.thrust_coefficient = FLAGS_thrust_coefficient;
    if (FLAGS_mass > 0.0) options.mass = FLAGS_mass;
    options.bag_topics = FLAGS_topics;
    options.calibration = FLAGS_calibration;
    const hdvio::io::DatasetFormat format = hdvio::io::detectFormat(argv[1]);
    const hdvio::Sequence seq = hdvio::io::readSequence(argv[1], options);
    std::printf("format:   %s\n%s", hdvio::io::formatName(format),
                hdvio::io::formatSummary(hdvio::io::summarize(seq)).c_str());
    return 0;
  });
}
