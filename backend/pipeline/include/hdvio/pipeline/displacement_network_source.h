#pragma once
// The learned displacement network (learned/displacement_model.h), or an ensemble of them, as the IMO filter's
// displacement source (backend/imo displacement_source.h): over each requested window, the
// network's displacement with the filter's orientation (learned::makeDisplacementWindow).
#include <memory>
#include <optional>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/learned/displacement_ensemble.h"

namespace hdvio {

// imu and thrust may grow while the source lives (a streaming estimator's buffers). No estimate
// where the IMU (or, for a thrust network, the thrust) does not cover the window yet.
// repeat_next_at (filter.release_first_window_sample, the IMO release's input buffer): in the
// windows, the IMU and thrust samples at that time take the next samples' values.
// The source holds the network's scratch memory: calls on one source object must not overlap
// (copies of it are independent).
// An ensemble's members read the same window (learned/displacement_ensemble.h).
imo::DisplacementSource networkDisplacementSource(
    std::shared_ptr<const learned::DisplacementEnsemble> networks,
    std::shared_ptr<const std::vector<ImuSample>> imu,
    std::shared_ptr<const std::vector<ThrustSample>> thrust,
    std::optional<Timestamp> repeat_next_at = std::nullopt);
// One network.
imo::DisplacementSource networkDisplacementSource(
    std::shared_ptr<const learned::DisplacementModel> model,
    std::shared_ptr<const std::vector<ImuSample>> imu,
    std::shared_ptr<const std::vector<ThrustSample>> thrust,
    std::optional<Timestamp> repeat_next_at = std::nullopt);

}  // namespace hdvio
