#include "hdvio/run/result_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "hdvio/core/error.h"

namespace hdvio::run {
namespace fs = std::filesystem;

namespace {
std::ofstream openOut(const fs::path& path) {
  std::ofstream f(path);
  if (!f) throw InputError(path.string(), 0, "cannot write output file");
  f.precision(9);
  f << std::fixed;
  return f;
}
}  // namespace

TimeQuantiles timeQuantiles(std::vector<double> ms) {
  TimeQuantiles q;
  if (ms.empty()) return {NAN, NAN, NAN, NAN};
  std::sort(ms.begin(), ms.end());
  const auto rank = [&ms](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(ms.size())));
    return ms[std::min(ms.size(), std::max<std::size_t>(k, 1)) - 1];
  };
  for (double x : ms) q.mean += x;
  q.mean /= static_cast<double>(ms.size());
  q.p50 = rank(0.5);
  q.p90 = rank(0.9);
  q.max = ms.back();
  return q;
}

std::vector<double> readImageProcessingMs(const std::string& path) {
  std::vector<double> ms;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    // #timestamp,load,frontend,backend,...
    double v[4];
    std::size_t pos = 0;
    bool ok = true;
    for (int i = 0; i < 4 && ok; ++i) {
      const std::size_t end = line.find(',', pos);
      ok = end != std::string::npos;
      if (ok) v[i] = std::atof(line.substr(pos, end - pos).c_str());
      pos = end + 1;
    }
    if (ok) ms.push_back(v[2] + v[3]);
  }
  return ms;
}

void checkOutputFolder(const std::string& out_dir) {
  const fs::path dir(out_dir);
  std::error_code ec;
  if (!fs::exists(dir, ec) || fs::is_empty(dir, ec)) return;
  if (!fs::is_directory(dir, ec))
    throw InputError(out_dir, 0, "output path exists and is not a folder");
  if (!fs::exists(dir / "stamped_traj_estimate.txt") || !fs::exists(dir / "config.yaml"))
    throw InputError(out_dir, 0,
                     "output folder is not empty and holds no earlier hdvio result; choose another");
}

void writeResults(const RunResults& r, const std::string& out_dir) {
  checkOutputFolder(out_dir);
  const fs::path final_dir(out_dir);
  const fs::path tmp = final_dir.string() + ".partial";
  std::error_code ec;
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp, ec);
  if (ec) throw InputError(tmp.string(), 0, "cannot create output folder: " + ec.message());

  auto traj = openOut(tmp / "stamped_traj_estimate.txt");
  traj << "# timestamp[s] tx ty tz qx qy qz qw\n";
  auto vel = openOut(tmp / "stamped_velocity_estimate.csv");
  vel << "#timestamp [ns],v_x [m s^-1],v_y [m s^-1],v_z [m s^-1]\n";
  auto bias = openOut(tmp / "stamped_bias_estimate.csv");
  bias << "#timestamp [ns],b_w_x [rad s^-1],b_w_y,b_w_z,b_a_x [m s^-2],b_a_y,b_a_z\n";
  const bool has_residual = r.has_force && !r.residual_force_B.empty();
  if (has_residual && r.residual_force_B.size() != r.states.size())
    throw std::logic_error("writeResults: one residual force per state expected");
  // Forces (FORMATS.md: IMU frame): external, learned residual (hdvio with a model) and the
  // total non-thrust force f_res + f_ext the dynamics use, the like-for-like quantity across
  // methods (for vimo / vid it equals f_ext).
  std::ofstream force, residual, total;
  if (r.has_force) {
    force = openOut(tmp / "stamped_force_estimate.csv");
    force << "#timestamp [ns],f_ext_x [m s^-2],f_ext_y [m s^-2],f_ext_z [m s^-2]\n";
    total = openOut(tmp / "stamped_total_force_estimate.csv");
    total << "#timestamp [ns],f_total_x [m s^-2],f_total_y [m s^-2],f_total_z [m s^-2]\n";
  }
  if (has_residual) {
    residual = openOut(tmp / "stamped_residual_force_estimate.csv");
    residual << "#timestamp [ns],f_res_x [m s^-2],f_res_y [m s^-2],f_res_z [m s^-2]\n";
  }
  for (std::size_t k = 0; k < r.states.size(); ++k) {
    const NavState& s = r.states[k];
    const Pose& T = s.T_WB;
    traj << toSeconds(s.t) << ' ' << T.p.x() << ' ' << T.p.y() << ' ' << T.p.z() << ' '
         << T.q.x() << ' ' << T.q.y() << ' ' << T.q.z() << ' ' << T.q.w() << '\n';
    vel << s.t << ',' << s.v_W.x() << ',' << s.v_W.y() << ',' << s.v_W.z() << '\n';
    bias << s.t;
    for (int i = 0; i < 6; ++i) bias << ',' << s.bias[i];
    bias << '\n';
    if (r.has_force) {
      const Vec3 f_body = T.q.conjugate() * s.f_ext_W;  // FORMATS.md: forces in the IMU frame
      force << s.t << ',' << f_body.x() << ',' << f_body.y() << ',' << f_body.z() << '\n';
      const Vec3 f_total = f_body + (has_residual ? r.residual_force_B[k] : Vec3::Zero());
      total << s.t << ',' << f_total.x() << ',' << f_total.y() << ',' << f_total.z() << '\n';
    }
    if (has_residual) {
      const Vec3& f = r.residual_force_B[k];
      residual << s.t << ',' << f.x() << ',' << f.y() << ',' << f.z() << '\n';
    }
  }
  auto timing = openOut(tmp / "timing.csv");
  timing << "#timestamp [ns],backend [ms],solver_iterations,landmarks,observations,keyframe\n";
  for (const auto& f : r.timing)
    timing << f.t << ',' << f.backend_ms << ',' << f.solver_iterations << ',' << f.landmarks << ','
           << f.observations << ',' << (f.keyframe ? 1 : 0) << '\n';
  auto stages = openOut(tmp / "timing_stages.csv");
  stages << "stage,total [s],calls,mean [ms],p50 [ms],p90 [ms],max [ms]\n";
  for (const auto& s : r.stages) {
    stages << s.stage << ',' << s.total_s << ',' << s.calls << ','
           << (s.calls > 0 ? 1e3 * s.total_s / s.calls : 0.0);
    if (s.call_ms.empty()) {
      stages << ",,,\n";
    } else {
      const TimeQuantiles q = timeQuantiles(s.call_ms);
      stages << ',' << q.p50 << ',' << q.p90 << ',' << q.max << '\n';
    }
  }
  std::ofstream images;
  if (!r.images.empty()) {
    images = openOut(tmp / "timing_images.csv");
    images << "#timestamp [ns],load [ms],frontend [ms],backend [ms],tracked_features,"
              "frontend_keyframe,used_by_backend\n";
    for (const ImageTiming& im : r.images)
      images << im.t << ',' << im.load_ms << ',' << im.frontend_ms << ',' << im.backend_ms << ','
             << im.tracked_features << ',' << (im.frontend_keyframe ? 1 : 0) << ','
             << (im.used_by_backend ? 1 : 0) << '\n';
  }
  auto cfg = openOut(tmp / "config.yaml");
  cfg << r.effective_config;
  for (auto* f : {&traj, &vel, &bias, &timing, &stages, &cfg}) {
    f->close();
    if (!*f) throw InputError(tmp.string(), 0, "writing results failed (disk full?)");
  }
  // Displacement-update innovations (inertial filters): residual, its predicted std per axis
  // (sqrt of S's diagonal) and the normalized innovation squared r' S^-1 r.
  std::ofstream innovations;
  if (!r.innovations.empty()) {
    innovations = openOut(tmp / "innovations.csv");
    innovations << "#timestamp [ns],r_x [m],r_y [m],r_z [m],sigma_x [m],sigma_y [m],sigma_z [m],nis,applied\n";
    for (const auto& u : r.innovations) {
      const imo::Innovation& in = u.innovation;
      innovations << u.t;
      for (int i = 0; i < 3; ++i) innovations << ',' << in.residual(i);
      for (int i = 0; i < 3; ++i) innovations << ',' << std::sqrt(in.covariance(i, i));
      innovations << ',' << in.nis << ',' << (u.applied ? 1 : 0) << '\n';
    }
  }
  for (auto* f : {&force, &residual, &total, &innovations, &images}) {
    if (!f->is_open()) continue;
    f->close();
    if (!*f) throw InputError(tmp.string(), 0, "writing results failed (disk full?)");
  }
  fs::remove_all(final_dir, ec);
  fs::rename(tmp, final_dir, ec);
  if (ec) throw InputError(final_dir.string(), 0, "cannot move results into place: " + ec.message());
}

}  // namespace hdvio::run
