#pragma once
// The rotation prior the frontend expects, from raw gyroscope samples.
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::frontend {

// R_{B(t0) B(t1)}: integration of (gyro - bias) over [t0, t1], each sample held until the next.
// Samples must be time ordered; returns identity when t1 <= t0 or no sample covers the span.
Quat integrateGyro(const std::vector<ImuSample>& imu, Timestamp t0, Timestamp t1,
                   const Vec3& gyro_bias = Vec3::Zero());

}  // namespace hdvio::frontend
