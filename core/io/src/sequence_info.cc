#include "hdvio/io/sequence_info.h"

#include <algorithm>
#include <cstdio>
#include <functional>

namespace hdvio::io {
namespace {

// Times plus a per-axis value accessor, reduced to counts, rates, gaps and ranges.
template <class T>
StreamSummary summarizeStream(const std::string& name, const std::vector<T>& samples,
                              const std::vector<std::string>& axes,
                              const std::function<double(const T&, std::size_t)>& value) {
  StreamSummary s;
  s.name = name;
  s.count = samples.size();
  if (samples.empty()) return s;
  s.first = samples.front().t;
  s.last = samples.back().t;
  s.span_s = secondsBetween(s.first, s.last);
  std::vector<double> dts;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const double dt = secondsBetween(samples[i - 1].t, samples[i].t);
    if (dt > 0.0) dts.push_back(dt);
  }
  if (!dts.empty()) {
    s.max_gap_s = *std::max_element(dts.begin(), dts.end());
    std::nth_element(dts.begin(), dts.begin() + dts.size() / 2, dts.end());
    s.rate_hz = 1.0 / dts[dts.size() / 2];
  }
  for (std::size_t a = 0; a < axes.size(); ++a) {
    AxisRange r{axes[a], value(samples.front(), a), value(samples.front(), a)};
    for (const T& x : samples) {
      r.min = std::min(r.min, value(x, a));
      r.max = std::max(r.max, value(x, a));
    }
    s.ranges.push_back(r);
  }
  return s;
}

MethodSupport method(const std::string& name, bool imu, bool cam, bool thrust, bool gt,
                     const Sequence& seq) {
  MethodSupport m;
  m.method = name;
  std::vector<std::string> needs, missing;
  auto need = [&](bool wanted, bool have, const char* what) {
    if (!wanted) return;
    needs.push_back(what);
    if (!have) missing.push_back(what);
  };
  need(imu, seq.hasImu(), "imu");
  need(cam, seq.hasImages(), "cam");
  need(thrust, seq.hasThrust(), "thrust");
  need(gt, seq.hasGroundTruth(), "groundtruth");
  for (const auto& n : needs) m.needs += (m.needs.empty() ? "" : "+") + n;
  for (const auto& n : missing) m.missing += (m.missing.empty() ? "" : ", ") + n;
  m.supported = missing.empty();
  return m;
}

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof(buf), format, a, b, c);
  return buf;
}

}  // namespace

SequenceSummary summarize(const Sequence& seq) {
  SequenceSummary out;
  out.name = seq.name;
  out.source = seq.source;
  out.warnings = seq.warnings;
  using V = std::vector<std::string>;
  out.streams.push_back(summarizeStream<ImuSample>(
      "imu0", seq.imu, {"gyro_x", "gyro_y", "gyro_z", "acc_x", "acc_y", "acc_z"},
      [](const ImuSample& s, std::size_t a) { return a < 3 ? s.gyro[a] : s.accel[a - 3]; }));
  if (!seq.images.empty())
    out.streams.push_back(summarizeStream<ImageRef>("cam0", seq.images, {}, nullptr));
  if (!seq.thrust.empty())
    out.streams.push_back(summarizeStream<ThrustSample>(
        "thrust0", seq.thrust, V{"T_x", "T_y", "T_z"}, [](const ThrustSample& s, std::size_t a) { return s.thrust[a]; }));
  if (!seq.rotor.empty())
    out.streams.push_back(summarizeStream<RotorSample>(
        "rotor0", seq.rotor, V{"w_1", "w_2", "w_3", "w_4"}, [](const RotorSample& s, std::size_t a) { return s.speeds[a]; }));
  if (!seq.groundtruth.empty())
    out.streams.push_back(summarizeStream<GroundTruthState>(
        "groundtruth", seq.groundtruth, V{"p_x", "p_y", "p_z", "v_x", "v_y", "v_z"},
        [](const GroundTruthState& s, std::size_t a) { return a < 3 ? s.T_WB.p[a] : s.v_W[a - 3]; }));
  if (!seq.forces.empty())
    out.streams.push_back(summarizeStream<ForceSample>(
        "forces", seq.forces, V{"ext_x", "ext_y", "ext_z", "drag_x", "drag_y", "drag_z"},
        [](const ForceSample& s, std::size_t a) { return a < 3 ? s.external[a] : s.drag[a - 3]; }));
  if (!seq.landmark_observations.empty())
    out.streams.push_back(summarizeStream<LandmarkObservation>("landmarks0", seq.landmark_observations, {}, nullptr));

  // Usable duration: the overlap of the streams the estimators consume together.
  Timestamp begin = seq.imu.front().t, end = seq.imu.back().t;
  auto clip = [&](Timestamp a, Timestamp b) {
    begin = std::max(begin, a);
    end = std::min(end, b);
  };
  if (!seq.images.empty()) clip(seq.images.front().t, seq.images.back().t);
  if (!seq.thrust.empty()) clip(seq.thrust.front().t, seq.thrust.back().t);
  else if (!seq.rotor.empty() && seq.rotor_calibration) clip(seq.rotor.front().t, seq.rotor.back().t);
  out.duration_s = std::max(0.0, secondsBetween(begin, end));

  if (!seq.groundtruth.empty() && seq.imu.size() > 1) {
    const Timestamp a = std::max(seq.imu.front().t, seq.groundtruth.front().t);
    const Timestamp b = std::min(seq.imu.back().t, seq.groundtruth.back().t);
    out.groundtruth_coverage =
        std::max(0.0, secondsBetween(a, b)) / secondsBetween(seq.imu.front().t, seq.imu.back().t);
  }

  out.methods = {method("vio", true, true, false, false, seq),
                 method("vimo", true, true, true, false, seq),
                 method("vid", true, true, true, false, seq),
                 method("hdvio", true, true, true, false, seq),
                 method("imo", true, false, true, false, seq),
                 method("model_ekf", true, false, true, false, seq),
                 method("net_only", true, false, true, false, seq),
                 method("tlio", true, false, false, false, seq),
                 method("evaluation", false, false, false, true, seq)};
  return out;
}

std::string formatSummary(const SequenceSummary& s) {
  std::string t = "name:     " + s.name + "\nsource:   " + s.source + "\n";
  t += fmt("duration: %.3f s (overlap of imu, camera and thrust streams)\n", s.duration_s);
  t += "streams:\n";
  for (const auto& st : s.streams) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "  %-12s %7zu samples  %8.3f Hz  span %8.3f s  max gap %.4f s\n",
                  st.name.c_str(), st.count, st.rate_hz, st.span_s, st.max_gap_s);
    t += buf;
    for (const auto& r : st.ranges) {
      std::snprintf(buf, sizeof(buf), "      %-8s [%12.5g, %12.5g]\n", r.axis.c_str(), r.min, r.max);
      t += buf;
    }
  }
  t += fmt("groundtruth coverage: %.1f %% of the IMU span\n", 100.0 * s.groundtruth_coverage);
  t += "warnings:" + std::string(s.warnings.empty() ? " none\n" : "\n");
  for (const auto& w : s.warnings) t += "  - " + w + "\n";
  t += "methods:\n";
  for (const auto& m : s.methods) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "  %-11s %-4s (needs %s%s%s)\n", m.method.c_str(),
                  m.supported ? "yes" : "no", m.needs.c_str(), m.missing.empty() ? "" : "; missing ",
                  m.missing.c_str());
    t += buf;
  }
  return t;
}

}  // namespace hdvio::io
