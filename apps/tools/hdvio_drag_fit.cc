// hdvio_drag_fit: fits the Model-EKF's thrust scale and linear rotor drag (docs/imo.md) on
// training flights by least squares against the accelerometer, f = k T - D v_body, and prints
// the thrust-vs-accelerometer check (world-frame mean / RMS of R (f - model)) before and after.
// With --drag_law it also fits the hybrid dynamics' drag law (linear + quadratic, docs/hdvio_story.md).
//   hdvio_drag_fit --data ../shared/data/blackbird/clover_yawForward_maxSpeed5p0/train
//   hdvio_drag_fit --data_root ../shared/data/dido --data <train flights> --thrust_coefficient_over_mass 1.025675e-06
#include <cstdio>
#include <sstream>

#include <gflags/gflags.h>

#include "hdvio/backend/imo/drag_model.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/sequence_reader.h"

DEFINE_string(data, "", "comma-separated training flights (any format hdvio_run reads)");
DEFINE_string(data_root, "", "prefix for relative --data paths");
DEFINE_double(thrust_coefficient_over_mass, 0.0,
              "C_T/m for flights without thrust: T = c * sum(w_i^2) along --thrust_axis z (as hdvio_run)");
DEFINE_bool(fit_thrust_scale, true, "fit the thrust scale k (else k = 1)");
DEFINE_bool(drag_law, false,
            "also fit the hybrid dynamics' drag law (linear + quadratic, thrust scale as fitted) "
            "and print it as backend keys for hdvio_run");

namespace {

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

void printVec(const char* label, const hdvio::Vec3& v) {
  std::printf("  %-28s %+.4f %+.4f %+.4f\n", label, v.x(), v.y(), v.z());
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_drag_fit --data <flight>[,<flight>...] [--drag_law]\n"
      "fits the Model-EKF thrust scale and rotor drag (and the hybrid drag law) on training flights\n"
      "example: hdvio_drag_fit --data ../shared/data/blackbird/clover_yawForward_maxSpeed5p0/train");
  return hdvio::runTool([] {
    if (FLAGS_data.empty()) throw hdvio::InputError("", 0, "--data is required");
    std::vector<hdvio::imo::DragSample> samples;
    for (const std::string& name : splitList(FLAGS_data)) {
      const std::string path = FLAGS_data_root.empty() ? name : FLAGS_data_root + "/" + name;
      const hdvio::Sequence seq = hdvio::io::readSequence(path);
      std::vector<hdvio::ThrustSample> thrust = hdvio::thrustSamples(seq);
      if (thrust.empty() && FLAGS_thrust_coefficient_over_mass > 0.0)
        for (const hdvio::RotorSample& r : seq.rotor)
          thrust.push_back({r.t, FLAGS_thrust_coefficient_over_mass * r.speeds.squaredNorm() *
                                     hdvio::Vec3::UnitZ()});
      if (thrust.empty()) throw hdvio::InputError(path, 0, "no thrust (give --thrust_coefficient_over_mass)");
      const auto s = hdvio::imo::collectDragSamples(seq, thrust);
      std::printf("%s: %zu samples\n", path.c_str(), s.size());
      samples.insert(samples.end(), s.begin(), s.end());
    }
    const hdvio::imo::DragFit fit = hdvio::imo::fitDragModel(samples, FLAGS_fit_thrust_scale);
    std::printf("samples %zu\n", fit.samples);
    std::printf("thrust_scale: %.6f\nlinear_drag: [%.6f, %.6f, %.6f]\n", fit.model.thrust_scale,
                fit.model.drag.linear.x(), fit.model.drag.linear.y(), fit.model.drag.linear.z());
    std::printf("world-frame residual R (f - model) [m/s^2], x y z:\n");
    printVec("thrust only (k 1, d 0) mean", fit.mean_thrust_only);
    printVec("thrust only rms", fit.rms_thrust_only);
    printVec("fitted mean", fit.mean_fitted);
    printVec("fitted rms", fit.rms_fitted);
    if (FLAGS_drag_law) {
      const hdvio::imo::DragLawFit law = hdvio::imo::fitDragLawOnSamples(samples, fit.model.thrust_scale);
      const hdvio::Vec3 &d = law.law.linear, &c = law.law.quadratic;
      std::printf("drag law (hybrid dynamics), backend keys:\n");
      std::printf("  drag_linear: [%.6f, %.6f, %.6f]\n  drag_quadratic: [%.6f, %.6f, %.6f]\n",
                  d.x(), d.y(), d.z(), c.x(), c.y(), c.z());
      printVec("drag law rms", law.rms);
    }
    return 0;
  });
}
