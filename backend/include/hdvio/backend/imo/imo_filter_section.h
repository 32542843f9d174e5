#pragma once
// What the inertial pipelines (imo/tlio/model_ekf/net_only and gate_io) read alike: the IMO
// filter's `filter:` section, into the run options beside it (imo_stepper.h ImoRunOptions, with
// imo_filter.h ImoFilterOptions) (docs/imo.md, docs/gate_io.md). Strict like every config:
// unknown keys are errors.
#include <string>

#include "hdvio/backend/imo/imo_stepper.h"
#include "hdvio/core/config.h"

namespace hdvio {

// A 3-vector key, `fallback` when absent.
Vec3 readVec3(const ConfigReader& r, const std::string& key, const Vec3& fallback);

namespace imo {

struct ImoFilterSection {
  ImoRunOptions* options = nullptr;  // filter noise, initial sigmas, rate, measurement sigma
  Vec3 init_gyro_bias = Vec3::Zero();
  Vec3 init_accel_bias = Vec3::Zero();
  // `release_first_window_sample`: in the network windows, the run's first IMU (and thrust)
  // sample takes the values of the second, as in the IMO release, whose input buffer starts
  // without a previous sample to interpolate from (NetInputBuffer.add_data_interpolated with
  // last_t_us < 0 stores the newer sample at the start time). Only the first window sees it.
  bool release_first_window_sample = false;
};

// Reads `filter:` into *section (defaults = what it holds) and calls f.finish(). InputError
// (naming config_path) for a non-positive measurement sigma.
void readImoFilterSection(const ConfigReader& f, const std::string& config_path,
                          ImoFilterSection* section);

}  // namespace imo
}  // namespace hdvio
