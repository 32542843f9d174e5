// hdvio_track: runs the semi-direct visual frontend on an ASL folder and prints, per image,
// the tracking stage, the number of tracked features and the time spent.
#include <gflags/gflags.h>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/asl.h"
#include "track_runner.h"

DEFINE_string(sequence, "", "ASL folder (containing mav0/) with cam0 images");
DEFINE_int32(max_frames, 0, "track at most this many images (0: all)");
DEFINE_bool(gyro_prior, true, "use the integrated gyroscope rotation as alignment prior");
DEFINE_bool(groundtruth_bootstrap, true,
            "while the frontend bootstraps, give it the ground-truth pose (no backend yet)");
DEFINE_string(trajectory, "", "write the tracked poses here (TUM order: t tx ty tz qx qy qz qw)");
DEFINE_bool(quiet, false, "print only the summary");

namespace {

double loadAverage() {
  std::ifstream f("/proc/loadavg");
  double l = -1.0;
  f >> l;
  return l;
}

void writeTrajectory(const hdvio::frontend::TrackRunSummary& s, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw hdvio::InputError(path, 0, "cannot write trajectory");
    out << "# timestamp[s] tx ty tz qx qy qz qw\n";
    char line[256];
    for (const auto& f : s.frames) {
      if (!f.result.tracked) continue;
      const auto& T = f.result.T_WB;
      // Seconds printed from the integer nanoseconds: a double would round the last digits.
      const long long t = f.result.t;
      std::snprintf(line, sizeof(line), "%lld.%09lld %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n",
                    t / 1000000000LL, t % 1000000000LL, T.p.x(), T.p.y(), T.p.z(), T.q.x(), T.q.y(),
                    T.q.z(), T.q.w());
      out << line;
    }
    if (!out) throw hdvio::InputError(path, 0, "cannot write trajectory");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw hdvio::InputError(path, 0, "cannot move trajectory into place");
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_track --sequence <ASL folder> [--max_frames N] [--trajectory out.txt]\n"
      "runs the semi-direct visual frontend and prints, per image, stage, tracked features and time\n"
      "example: hdvio_track --sequence ../shared/data/euroc/V1_01_easy_excerpt --max_frames 50");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_sequence})) return bad;
  return hdvio::runTool([] {
    if (FLAGS_max_frames < 0) throw hdvio::InputError("--max_frames", 0, "must be >= 0");
    const hdvio::Sequence seq = hdvio::io::readAsl(FLAGS_sequence);
    hdvio::frontend::TrackRunOptions options;
    options.max_frames = FLAGS_max_frames;
    options.gyro_prior = FLAGS_gyro_prior;
    options.groundtruth_bootstrap = FLAGS_groundtruth_bootstrap;
    const double load_before = loadAverage();
    if (!FLAGS_quiet)
      std::printf("%5s %16s %-13s %4s %8s %9s %7s %3s %7s %7s\n", "frame", "t[s]", "stage", "trk",
                  "features", "landmarks", "seeds", "kf", "ms", "pos_err");
    const auto summary = hdvio::frontend::runTracking(
        seq, options, [&](const hdvio::frontend::TrackedFrame& f) {
          if (FLAGS_quiet) return;
          const auto& r = f.result;
          char err[32] = "-";
          if (f.groundtruth_T_WB && r.tracked)
            std::snprintf(err, sizeof(err), "%.3f", (r.T_WB.p - f.groundtruth_T_WB->p).norm());
          std::printf("%5d %16.6f %-13s %4s %8d %9d %7d %3s %7.2f %7s%s\n", r.frame_id,
                      hdvio::toSeconds(r.t), hdvio::frontend::toString(r.stage).c_str(),
                      r.tracked ? "yes" : "NO", r.tracked_features, r.landmarks, r.seeds,
                      r.keyframe ? "KF" : "", r.timing.total_ms, err,
                      f.used_groundtruth ? "  (gt pose prior)" : "");
        });
    const double load_after = loadAverage();
    std::printf("summary: images %zu, tracked %d, lost %d, re-initializations %d, keyframes %d, "
                "ground-truth priors %d\n",
                summary.frames.size(), summary.tracked, summary.lost, summary.reinitializations,
                summary.keyframes, summary.groundtruth_priors);
    std::printf("features per tracked image (after the first): min %d, median %d\n",
                summary.min_features, summary.median_features);
    std::printf("time per image [ms] (single thread, image loading excluded): wall median %.2f, "
                "mean %.2f, max %.2f; thread CPU median %.2f, max %.2f; load average %.2f -> %.2f\n",
                summary.median_ms, summary.mean_ms, summary.max_ms, summary.median_cpu_ms,
                summary.max_cpu_ms, load_before, load_after);
    if (!FLAGS_trajectory.empty()) writeTrajectory(summary, FLAGS_trajectory);
    return 0;
  });
}
