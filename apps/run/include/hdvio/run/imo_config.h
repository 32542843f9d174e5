#pragma once
// What the inertial pipelines (imo/tlio/model_ekf/net_only and gate_io) read and build alike:
// the IMO filter's `filter:` section and the displacement network of a `network:` section
// (docs/imo.md, docs/gate_io.md). The network's displacement source is the pipeline's
// (backend/pipeline displacement_network_source.h).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/imo_stepper.h"
#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/learned/displacement_model.h"

namespace hdvio::run {

struct ImoFilterSection {
  imo::ImoRunOptions* options = nullptr;  // filter noise, initial sigmas, rate, measurement sigma
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

// A 3-vector key, `fallback` when absent.
Vec3 readVec3(const ConfigReader& r, const std::string& key, const Vec3& fallback);

// Loads `network: {weights: <file>}`, the path relative to the experiment file's folder;
// *weights (optional) receives the path as written.
std::shared_ptr<const learned::DisplacementModel> loadDisplacementNetwork(
    const ConfigReader& network, const std::string& experiment_dir, std::string* weights = nullptr);

// The IMU samples the inertial methods run on: from the first sample inside the ground truth
// (+ start_offset_s), for duration_s (<= 0: to the end). InputError when no sample is inside.
std::vector<ImuSample> imuSpanWithGroundTruth(const Sequence& seq, double start_offset_s,
                                              double duration_s);

}  // namespace hdvio::run
