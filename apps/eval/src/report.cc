#include "hdvio/eval/report.h"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hdvio/core/error.h"

namespace hdvio::eval {
namespace fs = std::filesystem;
namespace {

std::string num(double x, int precision = 4) {
  if (!std::isfinite(x)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", precision, x);
  return buf;
}

// Full precision for machines; NaN (no samples) becomes null.
std::string jnum(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

// ordered_json: metrics.json keeps its key order (tests scan the text after a key).
using Json = nlohmann::ordered_json;

// A number, or null when there is none (NaN: no samples).
Json jvalue(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json jstats(const ErrorStatistics& s) {
  return {{"count", s.count},         {"rmse", jvalue(s.rmse)}, {"mean", jvalue(s.mean)},
          {"median", jvalue(s.median)}, {"std", jvalue(s.std)},   {"min", jvalue(s.min)},
          {"max", jvalue(s.max)}};
}

Json jvector(const VectorErrors& e) {
  return {{"total", jstats(e.total)}, {"xy", jstats(e.xy)}, {"z", jstats(e.z)}};
}

std::string rpeLabel(const EvoRpeOptions& o) {
  std::ostringstream s;
  s << o.delta << (o.unit == DeltaUnit::kMeters ? " m" : " frames")
    << (o.all_pairs ? ", all pairs" : "");
  return s.str();
}

std::string csvPath(const std::string& dir, std::size_t index, const std::string& what) {
  return (fs::path(dir) / ("est" + std::to_string(index) + "_" + what + ".csv")).string();
}

}  // namespace

std::string formatTable(const EvaluationReport& report) {
  const EvaluationOptions& o = report.options;
  std::ostringstream t;
  t << "Ground truth: " << report.ground_truth_source << "  \n"
    << "Alignment: " << alignmentName(o.alignment)
    << (o.align_first_n > 0 ? " (first " + std::to_string(o.align_first_n) + " poses)" : " (all poses)")
    << ", association: " << associationName(o.association.mode);
  if (o.association.mode != AssociationMode::kIndex)
    t << " (max diff " << o.association.max_time_diff_s << " s, offset " << o.association.time_offset_s << " s)";
  t << "\n\n### Absolute trajectory error\n\n"
    << "| estimate | matched/poses | ATE rmse [m] | mean [m] | median [m] | max [m] | min [m] | rot rmse [deg] | RPE rmse [m] (evo, "
    << rpeLabel(o.evo_rpe_options) << ") | RPE rot rmse [deg] | velocity rmse [m/s] |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : report.results) {
    t << "| " << r.name << " | " << r.num_matched << "/" << r.num_poses << " | "
      << num(r.ate_translation.rmse) << " | " << num(r.ate_translation.mean) << " | "
      << num(r.ate_translation.median) << " | " << num(r.ate_translation.max) << " | "
      << num(r.ate_translation.min) << " | " << num(r.ate_rotation_deg.rmse, 3) << " | "
      << (r.evo_rpe ? num(r.evo_rpe_translation.rmse) : "-") << " | "
      << (r.evo_rpe ? num(r.evo_rpe_rotation_deg.rmse, 3) : "-") << " | "
      << (r.velocity ? num(r.velocity->total.rmse) : "-") << " |\n";
  }
  if (!report.distances.empty()) {
    t << "\n### Relative error (rpg toolbox sub-trajectories)\n\n"
      << "| estimate | length [m] | samples | trans median [m] | trans mean [m] | trans mean [%] | rot mean [deg] | yaw mean [deg] |\n"
      << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : report.results)
      for (const auto& s : r.relative)
        t << "| " << r.name << " | " << num(s.distance, 2) << " | " << s.translation.count << " | "
          << num(s.translation.median) << " | " << num(s.translation.mean) << " | "
          << num(s.translation_percent.mean, 3) << " | " << num(s.rotation_deg.mean, 3) << " | "
          << num(s.yaw_deg.mean, 3) << " |\n";
  }
  bool any_force = false;
  for (const auto& r : report.results) any_force = any_force || r.force.has_value();
  if (any_force) {
    t << "\n### Force (mass-normalized, IMU frame) RMSE [m/s^2]\n\n"
      << "| estimate | samples | external total | external xy | external z | total-force total | total-force xy | total-force z |\n"
      << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : report.results) {
      if (!r.force) continue;
      const ForceErrors& f = *r.force;
      t << "| " << r.name << " | " << f.external.total.count << " | " << num(f.external.total.rmse)
        << " | " << num(f.external.xy.rmse) << " | " << num(f.external.z.rmse) << " | "
        << num(f.total.total.rmse) << " | " << num(f.total.xy.rmse) << " | " << num(f.total.z.rmse) << " |\n";
    }
  }
  for (const auto& r : report.results)
    for (const auto& note : r.notes) t << "\nnote (" << r.name << "): " << note;
  t << "\n";
  return t.str();
}

std::string formatJson(const EvaluationReport& report) {
  const EvaluationOptions& o = report.options;
  Json estimates = Json::array();
  for (std::size_t i = 0; i < report.results.size(); ++i) {
    const EstimateResult& r = report.results[i];
    Json rotation = Json::array();
    for (int a = 0; a < 9; ++a) rotation.push_back(jvalue(r.alignment.R(a / 3, a % 3)));
    Json relative = Json::array();
    for (const RelativeErrorSummary& s : r.relative)
      relative.push_back({{"distance_m", jvalue(s.distance)},
                          {"translation_m", jstats(s.translation)},
                          {"translation_percent", jstats(s.translation_percent)},
                          {"rotation_deg", jstats(s.rotation_deg)},
                          {"yaw_deg", jstats(s.yaw_deg)}});
    estimates.push_back(
        {{"name", r.name},
         {"index", i},
         {"source", r.source},
         {"poses", r.num_poses},
         {"matched", r.num_matched},
         {"alignment",
          {{"scale", jvalue(r.alignment.s)},
           {"rotation", rotation},
           {"translation",
            {jvalue(r.alignment.t.x()), jvalue(r.alignment.t.y()), jvalue(r.alignment.t.z())}}}},
         {"ate_translation_m", jstats(r.ate_translation)},
         {"ate_rotation_deg", jstats(r.ate_rotation_deg)},
         {"evo_rpe_translation_m", r.evo_rpe ? jstats(r.evo_rpe_translation) : Json(nullptr)},
         {"evo_rpe_rotation_deg", r.evo_rpe ? jstats(r.evo_rpe_rotation_deg) : Json(nullptr)},
         {"relative_errors", relative},
         {"velocity_m_s", r.velocity ? jvector(*r.velocity) : Json(nullptr)},
         {"force_external_m_s2", r.force ? jvector(r.force->external) : Json(nullptr)},
         {"force_total_m_s2", r.force ? jvector(r.force->total) : Json(nullptr)},
         {"notes", r.notes}});
  }
  const Json j = {
      {"ground_truth", report.ground_truth_source},
      {"options",
       {{"alignment", alignmentName(o.alignment)},
        {"align_first_n", o.align_first_n},
        {"association", associationName(o.association.mode)},
        {"max_time_diff_s", jvalue(o.association.max_time_diff_s)},
        {"time_offset_s", jvalue(o.association.time_offset_s)},
        {"evo_rpe_delta", jvalue(o.evo_rpe_options.delta)},
        {"evo_rpe_unit", o.evo_rpe_options.unit == DeltaUnit::kMeters ? "m" : "f"},
        {"evo_rpe_all_pairs", o.evo_rpe_options.all_pairs}}},
      {"estimates", estimates}};
  // replace: a name or note with invalid UTF-8 must not make the whole report fail.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw InputError(path, 0, "cannot write file");
    out << text;
    if (!out) throw InputError(path, 0, "write failed");
  }
  fs::rename(tmp, path);
}

void writeReport(const EvaluationReport& report, const GroundTruth& gt, const std::string& out_dir) {
  std::error_code ec;
  const fs::path plot_dir = fs::path(out_dir) / "plot_data";
  fs::create_directories(plot_dir, ec);
  if (ec) throw InputError(out_dir, 0, "cannot create output folder: " + ec.message());

  std::ostringstream g;
  g << "# t_s,x,y,z\n";
  const Trajectory& gtt = gt.trajectory;
  for (std::size_t i = 0; i < gtt.size(); ++i)
    g << jnum(secondsBetween(gtt.t.front(), gtt.t[i])) << "," << jnum(gtt.p[i].x()) << ","
      << jnum(gtt.p[i].y()) << "," << jnum(gtt.p[i].z()) << "\n";
  writeFileAtomically((plot_dir / "groundtruth.csv").string(), g.str());

  const Timestamp t0 = gtt.t.front();
  for (std::size_t k = 0; k < report.results.size(); ++k) {
    const EstimateResult& r = report.results[k];
    std::ostringstream a;
    a << "# t_s,x,y,z,gt_x,gt_y,gt_z,ate_m\n";
    for (std::size_t i = 0; i < r.est_aligned.size(); ++i) {
      const Vec3& p = r.est_aligned.p[i];
      const Vec3& q = r.ref_matched.p[i];
      a << jnum(secondsBetween(t0, r.ref_matched.t[i])) << "," << jnum(p.x()) << "," << jnum(p.y())
        << "," << jnum(p.z()) << "," << jnum(q.x()) << "," << jnum(q.y()) << "," << jnum(q.z()) << ","
        << jnum(r.ate.translation[i]) << "\n";
    }
    writeFileAtomically(csvPath(plot_dir.string(), k, "aligned"), a.str());

    std::ostringstream rel;
    rel << "# distance_m,translation_m,translation_percent,rotation_deg\n";
    for (const auto& s : r.relative)
      for (std::size_t i = 0; i < s.errors.translation.size(); ++i)
        rel << jnum(s.distance) << "," << jnum(s.errors.translation[i]) << ","
            << jnum(s.errors.translation_percent[i]) << "," << jnum(s.errors.rotation_deg[i]) << "\n";
    writeFileAtomically(csvPath(plot_dir.string(), k, "relative"), rel.str());

    if (r.force) {
      std::ostringstream f;
      // total_est: the estimate's total non-thrust force (hdvio: residual + external; else the
      // external estimate again), matched at the same stamps.
      f << "# t_s,est_x,est_y,est_z,ext_x,ext_y,ext_z,total_x,total_y,total_z,total_est_x,total_est_y,"
           "total_est_z\n";
      const VectorErrors& e = r.force->external;
      const VectorErrors& tot = r.force->total;
      const std::size_t n = std::min(e.t.size(), tot.t.size());
      for (std::size_t i = 0; i < n; ++i)
        f << jnum(secondsBetween(t0, e.t[i])) << "," << jnum(e.estimate[i].x()) << ","
          << jnum(e.estimate[i].y()) << "," << jnum(e.estimate[i].z()) << "," << jnum(e.truth[i].x())
          << "," << jnum(e.truth[i].y()) << "," << jnum(e.truth[i].z()) << ","
          << jnum(tot.truth[i].x()) << "," << jnum(tot.truth[i].y()) << "," << jnum(tot.truth[i].z())
          << "," << jnum(tot.estimate[i].x()) << "," << jnum(tot.estimate[i].y()) << ","
          << jnum(tot.estimate[i].z()) << "\n";
      writeFileAtomically(csvPath(plot_dir.string(), k, "force"), f.str());
    }
  }
  writeFileAtomically((fs::path(out_dir) / "table.md").string(), formatTable(report));
  // Last: its presence marks a complete result.
  writeFileAtomically((fs::path(out_dir) / "metrics.json").string(), formatJson(report));
}

}  // namespace hdvio::eval
