// Physics of the simulator: IMU integration reproduces the truth, the accelerometer is the
// rotated (a - g), thrust + drag + external = specific force, noise statistics, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "hdvio/core/error.h"
#include "hdvio/sim/simulator.h"
#include "sim_test_util.h"

namespace hdvio::sim {
namespace {

using testing::aggressiveInertialConfig;

struct NavState {
  Quat q;
  Vec3 v, p;
};
struct NavRate {
  Eigen::Vector4d dq;  // quaternion coefficients (w, x, y, z)
  Vec3 dv, dp;
};

NavRate rate(const NavState& s, const ImuSample& m) {
  const Quat w(0.0, 0.5 * m.gyro.x(), 0.5 * m.gyro.y(), 0.5 * m.gyro.z());
  const Quat dq = s.q * w;
  return {Eigen::Vector4d(dq.w(), dq.x(), dq.y(), dq.z()), s.q * m.accel + gravityWorld(), s.v};
}

NavState step(const NavState& s, const NavRate& r, double h) {
  NavState o;
  o.q = Quat(s.q.w() + h * r.dq[0], s.q.x() + h * r.dq[1], s.q.y() + h * r.dq[2], s.q.z() + h * r.dq[3]);
  o.v = s.v + h * r.dv;
  o.p = s.p + h * r.dp;
  return o;
}

// Classical RK4 over two IMU periods, using only the recorded samples k, k+1 (midpoint), k+2.
NavState rk4(const NavState& s, const ImuSample& m0, const ImuSample& m1, const ImuSample& m2, double H) {
  const NavRate k1 = rate(s, m0);
  const NavRate k2 = rate(step(s, k1, H / 2), m1);
  const NavRate k3 = rate(step(s, k2, H / 2), m1);
  const NavRate k4 = rate(step(s, k3, H), m2);
  NavState o;
  const Eigen::Vector4d q0(s.q.w(), s.q.x(), s.q.y(), s.q.z());
  const Eigen::Vector4d q = q0 + H / 6.0 * (k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq);
  o.q = Quat(q[0], q[1], q[2], q[3]).normalized();
  o.v = s.v + H / 6.0 * (k1.dv + 2.0 * k2.dv + 2.0 * k3.dv + k4.dv);
  o.p = s.p + H / 6.0 * (k1.dp + 2.0 * k2.dp + 2.0 * k3.dp + k4.dp);
  return o;
}

// Integrates the recorded noise-free IMU from the true initial state (RK4 over pairs of
// samples) and returns the largest position / rotation error against the recorded truth.
void integrateAndCompare(const Sequence& seq, double* max_pos, double* max_rot, double* peak_speed) {
  const double H = 2.0 / seq.imu_calibration->rate_hz;
  NavState s{seq.groundtruth[0].T_WB.q, seq.groundtruth[0].v_W, seq.groundtruth[0].T_WB.p};
  *max_pos = *max_rot = *peak_speed = 0.0;
  for (size_t k = 0; k + 2 < seq.imu.size(); k += 2) {
    s = rk4(s, seq.imu[k], seq.imu[k + 1], seq.imu[k + 2], H);
    const GroundTruthState& gt = seq.groundtruth[k + 2];
    *max_pos = std::max(*max_pos, (s.p - gt.T_WB.p).norm());
    *max_rot = std::max(*max_rot, quatLog(gt.T_WB.q.conjugate() * s.q).norm());
    *peak_speed = std::max(*peak_speed, gt.v_W.norm());
  }
}

TEST(SimDynamics, NoiseFreeImuIntegrationReproducesTruthOver10s) {
  const Simulator sim(aggressiveInertialConfig(10.0));
  const SimulationResult r = sim.simulate();
  ASSERT_EQ(r.sequence.imu.size(), 2001u);  // 10 s at 200 Hz, both ends included
  double max_pos, max_rot, peak_speed;
  integrateAndCompare(r.sequence, &max_pos, &max_rot, &peak_speed);
  std::printf("random flight, RK4 on 200 Hz samples, 10 s: max position error %.3g m, rotation %.3g rad\n",
              max_pos, max_rot);
  EXPECT_NEAR(peak_speed, 6.0, 0.01);
  EXPECT_LT(max_pos, 1e-3);
  EXPECT_LT(max_rot, 1e-5);
}

TEST(SimDynamics, NoiseFreeImuIntegrationAt15MetersPerSecond) {
  const Simulator sim(testing::raceConfig(10.0));
  const SimulationResult r = sim.simulate();
  double max_pos, max_rot, peak_speed;
  integrateAndCompare(r.sequence, &max_pos, &max_rot, &peak_speed);
  std::printf("race at 15 m/s, RK4 on 200 Hz samples, 10 s: max position error %.3g m, rotation %.3g rad\n",
              max_pos, max_rot);
  EXPECT_GT(peak_speed, 14.0);
  EXPECT_LT(max_pos, 1e-3);
  EXPECT_LT(max_rot, 1e-5);
}

TEST(SimDynamics, AccelerometerIsRotatedAccelerationMinusGravity) {
  // Independent check of the series machinery: finite differences of the true trajectory.
  const Simulator sim(aggressiveInertialConfig(6.0));
  const VehicleModel& m = sim.model();
  const double h = 1e-3;
  double max_acc = 0.0, max_gyro = 0.0, max_vel = 0.0;
  for (double t = 0.5; t < 5.5; t += 0.137) {
    const TrueState s = m.evaluate(t), sm = m.evaluate(t - h), sp = m.evaluate(t + h);
    const Vec3 a_fd = (sp.p - 2.0 * s.p + sm.p) / (h * h);
    const Vec3 v_fd = (sp.p - sm.p) / (2.0 * h);
    const Vec3 w_fd = so3Log(sm.R.transpose() * sp.R) / (2.0 * h);
    max_acc = std::max(max_acc, (s.specific_force - s.R.transpose() * (a_fd - gravityWorld())).norm());
    max_vel = std::max(max_vel, (s.v - v_fd).norm());
    max_gyro = std::max(max_gyro, (s.omega - w_fd).norm());
  }
  EXPECT_LT(max_acc, 1e-3);   // finite-difference truncation ~h^2 * |p''''| and round-off
  EXPECT_LT(max_vel, 1e-4);
  EXPECT_LT(max_gyro, 1e-4);
  // And the written accelerometer (noise-free, zero bias) is exactly that specific force.
  const SimulationResult r = sim.simulate();
  for (size_t k = 0; k < r.sequence.imu.size(); k += 97) {
    const TrueState& s = r.states[k];
    EXPECT_LT((r.sequence.imu[k].accel - s.R.transpose() * (s.a - gravityWorld())).norm(), 1e-9);
  }
}

TEST(SimDynamics, ThrustPlusDragPlusExternalEqualsSpecificForce) {
  const Simulator sim(aggressiveInertialConfig(9.0));
  const SimulationResult r = sim.simulate();
  const Sequence& seq = r.sequence;
  ASSERT_EQ(seq.thrust.size(), seq.imu.size());
  ASSERT_EQ(seq.forces.size(), seq.imu.size());
  double max_residual = 0.0, max_ext = 0.0, max_drag = 0.0;
  const VehicleConfig& veh = sim.config().vehicle;
  for (size_t k = 0; k < seq.imu.size(); ++k) {
    const Vec3 sum = seq.thrust[k].thrust + seq.forces[k].drag + seq.forces[k].external;
    max_residual = std::max(max_residual, (sum - seq.imu[k].accel).norm());
    max_ext = std::max(max_ext, seq.forces[k].external.norm());
    max_drag = std::max(max_drag, seq.forces[k].drag.norm());
    // The drag written is the model's drag for the true airspeed.
    const TrueState& s = r.states[k];
    const Vec3 v_rel = s.R.transpose() * (s.v - s.wind);
    const Vec3 expected = -(veh.rotor_drag.asDiagonal() * v_rel) -
                          veh.fuselage_drag * std::sqrt(v_rel.squaredNorm() + 1e-6) * v_rel;
    ASSERT_LT((expected - seq.forces[k].drag).norm(), 1e-9) << "sample " << k;
  }
  EXPECT_LT(max_residual, 1e-9);
  EXPECT_GT(max_ext, 1.5);   // the pull and the payload really act
  EXPECT_GT(max_drag, 1.0);  // drag is not negligible at 6 m/s plus wind
}

TEST(SimDynamics, ThrustChannelMiscalibrationLagAndRotorSpeeds) {
  SimConfig c = aggressiveInertialConfig(4.0);
  c.vehicle.thrust_output = VehicleConfig::ThrustOutput::kCommanded;
  c.vehicle.thrust_scale = 1.1;
  c.vehicle.thrust_bias = -0.3;
  c.vehicle.thrust_lag = 0.05;
  const Simulator sim(c);
  const SimulationResult r = sim.simulate();
  const Sequence& seq = r.sequence;
  const double dt = 1.0 / c.imu.rate_hz;
  for (size_t k = 1; k + 1 < seq.thrust.size(); k += 13) {
    // command = scale * (T + lag dT/dt) + bias, dT/dt checked by central differences
    const double dT = (r.states[k + 1].thrust - r.states[k - 1].thrust) / (2.0 * dt);
    const double expected = 1.1 * (r.states[k].thrust + 0.05 * dT) - 0.3;
    EXPECT_NEAR(seq.thrust[k].thrust.z(), expected, 2e-3);
    // rotor speeds reproduce the written thrust through C_T / m * sum(w^2)
    const RotorCalibration& rc = *seq.rotor_calibration;
    const double from_rotors = rc.thrust_coefficient / rc.mass * seq.rotor[k].speeds.squaredNorm();
    EXPECT_NEAR(from_rotors, seq.thrust[k].thrust.z(), 1e-9);
  }
  EXPECT_EQ(r.clamped_rotor_samples, 0);
}

TEST(SimDynamics, ImuNoiseAndBiasRandomWalkMatchDensities) {
  SimConfig c = aggressiveInertialConfig(10.0);
  c.imu.noise = true;
  c.imu.gyro_noise_density = 1e-3;
  c.imu.accel_noise_density = 2e-2;
  c.imu.gyro_random_walk = 1e-4;
  c.imu.accel_random_walk = 1e-3;
  const Simulator sim(c);
  const SimulationResult r = sim.simulate();
  const Sequence& seq = r.sequence;
  const double dt = 1.0 / c.imu.rate_hz;
  double g2 = 0.0, a2 = 0.0, bg2 = 0.0, ba2 = 0.0;
  const size_t n = seq.imu.size();
  for (size_t k = 0; k < n; ++k) {
    const GroundTruthState& gt = seq.groundtruth[k];
    g2 += (seq.imu[k].gyro - r.states[k].omega - gt.gyro_bias).squaredNorm();
    a2 += (seq.imu[k].accel - r.states[k].specific_force - gt.accel_bias).squaredNorm();
    if (k > 0) {
      bg2 += (gt.gyro_bias - seq.groundtruth[k - 1].gyro_bias).squaredNorm();
      ba2 += (gt.accel_bias - seq.groundtruth[k - 1].accel_bias).squaredNorm();
    }
  }
  const double samples = 3.0 * n;
  EXPECT_NEAR(std::sqrt(g2 / samples), 1e-3 / std::sqrt(dt), 0.03 * 1e-3 / std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(a2 / samples), 2e-2 / std::sqrt(dt), 0.03 * 2e-2 / std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(bg2 / (samples - 3)), 1e-4 * std::sqrt(dt), 0.03 * 1e-4 * std::sqrt(dt));
  EXPECT_NEAR(std::sqrt(ba2 / (samples - 3)), 1e-3 * std::sqrt(dt), 0.03 * 1e-3 * std::sqrt(dt));
}

TEST(SimDynamics, DeterministicForASeed) {
  SimConfig c = aggressiveInertialConfig(2.0);
  c.imu.noise = true;
  const SimulationResult a = Simulator(c).simulate(), b = Simulator(c).simulate();
  c.seed += 1;
  const SimulationResult other = Simulator(c).simulate();
  ASSERT_EQ(a.sequence.imu.size(), b.sequence.imu.size());
  for (size_t k = 0; k < a.sequence.imu.size(); ++k) {
    ASSERT_EQ(a.sequence.imu[k].accel, b.sequence.imu[k].accel);
    ASSERT_EQ(a.sequence.imu[k].gyro, b.sequence.imu[k].gyro);
  }
  EXPECT_GT((a.sequence.groundtruth.back().T_WB.p - other.sequence.groundtruth.back().T_WB.p).norm(), 0.1);
}

TEST(SimDynamics, ReachesFifteenMetersPerSecondOnARaceTrack) {
  const SimConfig c = testing::raceConfig(12.0);
  const Simulator sim(c);
  EXPECT_NEAR(sim.model().trajectory().peakSpeed(), 15.0, 0.01);
  // The flight passes through every gate centre.
  const std::vector<GateConfig> gates = sim.model().trajectory().orientedGates();
  for (const GateConfig& g : gates) {
    double closest = 1e9;
    for (double t = 0.0; t <= c.duration; t += 0.002)
      closest = std::min(closest, (sim.model().evaluate(t).p - g.position).norm());
    EXPECT_LT(closest, 0.05);
  }
}

TEST(SimDynamics, ImpossibleFlightsAreInputErrors) {
  SimConfig c = aggressiveInertialConfig(10.0);
  c.trajectory.max_speed = 25.0;  // vertical swings at 25 m/s would need negative thrust
  c.trajectory.extent = Vec3(6.0, 4.0, 2.5);
  c.trajectory.center.z() = 6.0;
  c.scene.room_max.z() = 12.0;
  try {
    Simulator s(c);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not flyable"), std::string::npos) << e.what();
  }
  SimConfig d = aggressiveInertialConfig(10.0);
  d.trajectory.extent = Vec3(12.0, 4.0, 1.0);  // wider than the hall
  try {
    Simulator s(d);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the room"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hdvio::sim
