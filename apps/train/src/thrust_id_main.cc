// hdvio_thrust_id: identifies C_T / m (and C_T for a given mass) from rotor speeds and the
// accelerometer, for datasets that publish no thrust model (DIDO, NeuroBEM).
#include <cstdio>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/thrust_identification.h"
#include "hdvio/train/flight_loading.h"

DEFINE_string(data, "", "comma-separated flights (NeuroBEM .csv, DIDO folder, ASL folder with rotor0)");
DEFINE_string(data_root, "", "prefix for relative --data paths (e.g. ../shared/data)");
DEFINE_double(mass, 0.0, "vehicle mass in kg for reporting C_T (0: C_T/m only)");
DEFINE_bool(fit_drag, false, "also fit linear drag d (drag = -d .* v_body)");
DEFINE_double(begin_fraction, 0.0, "use rotor samples from this fraction of each flight ...");
DEFINE_double(end_fraction, 1.0, "... up to this fraction (hold out the rest)");

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_thrust_id --data_root <dir> --data <flight>[,<flight>...] [--mass m]\n"
      "identifies the thrust coefficient from rotor speeds and the accelerometer\n"
      "example: hdvio_thrust_id --data_root ../shared/data --data neurobem/a.csv,neurobem/b.csv --mass 0.772");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_data})) return bad;
  return hdvio::runTool([] {
    if (!(FLAGS_begin_fraction >= 0.0 && FLAGS_begin_fraction < FLAGS_end_fraction && FLAGS_end_fraction <= 1.0)) {
      throw hdvio::InputError("", 0, "need 0 <= --begin_fraction < --end_fraction <= 1");
    }
    std::vector<hdvio::Sequence> flights;
    hdvio::train::FlightSource source;
    source.data_root = FLAGS_data_root;
    for (const auto& path : hdvio::train::splitList(FLAGS_data)) {
      flights.push_back(hdvio::train::loadSequence(path, source));
      std::printf("%s: %zu rotor samples\n", path.c_str(), flights.back().rotor.size());
    }
    hdvio::learned::ThrustFitOptions options;
    options.fit_linear_drag = FLAGS_fit_drag;
    const hdvio::learned::ThrustFit fit = hdvio::learned::fitThrustJointly(flights, options, FLAGS_begin_fraction, FLAGS_end_fraction);
    std::printf("samples            %zu\n", fit.samples);
    std::printf("C_T/m              %.6e m s^-2 / (rad/s)^2\n", fit.c_over_m);
    if (FLAGS_mass > 0.0) std::printf("C_T (m = %.4f kg) %.6e N s^2 rad^-2\n", FLAGS_mass, fit.thrustCoefficient(FLAGS_mass));
    std::printf("thrust axis        %+.0f %+.0f %+.0f (body)\n", fit.thrust_axis.x(), fit.thrust_axis.y(), fit.thrust_axis.z());
    if (FLAGS_fit_drag) std::printf("linear drag d      %.4f %.4f %.4f 1/s\n", fit.linear_drag.x(), fit.linear_drag.y(), fit.linear_drag.z());
    std::printf("RMSE along axis    %.4f m/s^2\n", fit.rmse_axis);
    std::printf("RMSE 3-D           %.4f m/s^2\n", fit.rmse_total);
    return 0;
  });
}
