// The visual estimator fed from a program, as a live system feeds it: the IMU up to each camera
// image, then the image; a state for every image once started. The same object hdvio_run drives.
//   hdvio_stream_example <ASL folder with cam0, imu0 and their sensor.yaml>
#include <cstdio>

#include "hdvio/core/tool_main.h"
#include "hdvio/io/image.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/pipeline/visual_estimator.h"

int main(int argc, char** argv) {
  using namespace hdvio;
  if (argc != 2) return std::fprintf(stderr, "usage: %s <ASL folder>\n", argv[0]), kExitBadInput;
  return runTool([&] {
    const Sequence seq = io::readSequence(argv[1]);
    if (!seq.camera || !seq.imu_calibration)
      throw InputError(argv[1], 0, "needs cam0 and imu0 with their sensor.yaml");
    VisualEstimatorOptions options;  // vio on images; the static or visual-inertial start
    options.backend = defaultVioBackendOptions(VioMethod::kVio);
    adoptImuNoise(*seq.imu_calibration, ConfigReader::fromString("{}"), &options.backend);
    VisualEstimator estimator(options, *seq.camera);
    std::size_t imu = 0;
    for (const ImageRef& image : seq.images) {
      while (imu < seq.imu.size() && seq.imu[imu].t <= image.t) estimator.addImu(seq.imu[imu++]);
      const ImageStep step = estimator.addImage(image.t, io::loadImage(image, &*seq.camera));
      if (!step.result) continue;  // not started yet (or no state for this image)
      const NavState& s = step.result->state;
      std::printf("%.3f  p %7.3f %7.3f %7.3f  v %6.2f %6.2f %6.2f\n", toSeconds(s.t),
                  s.T_WB.p.x(), s.T_WB.p.y(), s.T_WB.p.z(), s.v_W.x(), s.v_W.y(), s.v_W.z());
    }
    return 0;
  });
}
