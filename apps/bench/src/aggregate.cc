#include "hdvio/bench/aggregate.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hdvio/bench/process_pool.h"
#include "hdvio/eval/estimate_inputs.h"
#include "hdvio/eval/report.h"
#include "hdvio/run/run_evaluation.h"
#include "hdvio/run/result_writer.h"

namespace hdvio::bench {
namespace fs = std::filesystem;

namespace {

std::string estimateName(const RunJob& j) {
  return j.seed ? j.experiment + ".s" + std::to_string(*j.seed) : j.experiment;
}

double readNumber(const std::string& path) {
  std::ifstream in(path);
  double x = NAN;
  return (in >> x) ? x : NAN;
}

void fillMetrics(const eval::EstimateResult& r, RunMetrics* m) {
  m->ate_t_m = r.ate_translation.rmse;
  m->ate_r_deg = r.ate_rotation_deg.rmse;
  if (r.evo_rpe) m->rpe_t_m = r.evo_rpe_translation.rmse;
  if (r.velocity) m->velocity_rmse = r.velocity->total.rmse;
  if (r.force) {
    m->force_total_rmse = r.force->total.total.rmse;
    m->force_external_rmse = r.force->external.total.rmse;
  }
  m->poses = r.num_poses;
  m->matched = r.num_matched;
}

std::string num(double x, int precision) {
  if (!std::isfinite(x)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", precision, x);
  return buf;
}

std::string full(double x, const char* missing) {
  if (!std::isfinite(x)) return missing;
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

// ordered_json: results.json keeps its key order (tests scan the text after a run's "experiment").
using Json = nlohmann::ordered_json;

// A number, or null when the run has none (NaN).
Json jvalue(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json runJson(const RunMetrics& r) {
  Json stages = Json::object();
  for (const auto& [name, seconds] : r.stages) stages[name] = jvalue(seconds);
  return {{"sequence", r.job.sequence},
          {"experiment", r.job.experiment},
          {"seed", r.job.seed ? Json(*r.job.seed) : Json(nullptr)},
          {"status", r.status},
          {"ate_t_m", jvalue(r.ate_t_m)},
          {"ate_r_deg", jvalue(r.ate_r_deg)},
          {"rpe_t_m", jvalue(r.rpe_t_m)},
          {"velocity_rmse_m_s", jvalue(r.velocity_rmse)},
          {"force_total_rmse_m_s2", jvalue(r.force_total_rmse)},
          {"force_external_rmse_m_s2", jvalue(r.force_external_rmse)},
          {"matched", r.matched},
          {"poses", r.poses},
          {"runtime_s", jvalue(r.runtime_s)},
          {"duration_s", jvalue(r.duration_s)},
          {"realtime_factor", jvalue(r.realtime_factor)},
          {"process_wall_s", jvalue(r.process_wall_s)},
          {"stages", stages},
          {"result_dir", r.job.result_dir},
          {"log", r.job.log},
          {"error", r.error},
          {"peer", r.job.peer()},
          {"ms_per_image_mean", jvalue(r.ms_per_image_mean)},
          {"ms_per_image_median", jvalue(r.ms_per_image_median)},
          {"peer_timing", r.peer_timing},
          {"ms_per_image_p90", jvalue(r.ms_per_image_p90)}};
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// Mean of a metric over the completed runs (seeds) of one cell.
double cellMean(const std::vector<const RunMetrics*>& runs, double RunMetrics::*field) {
  double sum = 0.0;
  int n = 0;
  for (const RunMetrics* r : runs)
    if (r->status == "ok" && std::isfinite(r->*field)) {
      sum += r->*field;
      ++n;
    }
  return n ? sum / n : NAN;
}

std::string shorten(const std::string& s, std::size_t n) {
  return s.size() <= n ? s : s.substr(0, n - 3) + "...";
}

std::string markdownCell(const std::string& s) {
  std::string out;
  for (char c : s) out += (c == '|') ? std::string("\\|") : std::string(1, c);
  return out;
}

// The number after the word `key` (e.g. "mean 5.52"), NAN if absent.
double numberAfter(const std::string& line, const std::string& key) {
  std::istringstream in(line);
  std::string word;
  while (in >> word)
    if (word == key) {
      double x = NAN;
      return (in >> x) ? x : NAN;
    }
  return NAN;
}

// Below the runtime table: what each peer is, what its time counts, and its runs one by one.
std::string peerNotes(const Matrix& matrix, const std::vector<RunMetrics>& runs) {
  std::ostringstream t;
  t << "\nPeers run as `<command> <ASL folder> <out.txt>`, evaluated like the experiments. Their "
       "runtime is the mean time per image they print x images (what it counts: below); the "
       "experiments' is their summed stage time.\n";
  for (const MatrixPeer& p : matrix.peers) {
    t << "\n- " << p.name << ": `" << p.command << "`\n";
    for (const RunMetrics& r : runs) {
      if (r.job.experiment != p.name) continue;
      t << "  - " << r.job.sequence << (r.job.seed ? ", seed " + std::to_string(*r.job.seed) : "")
        << ": ";
      if (r.status == "ok" && std::isfinite(r.ms_per_image_mean))
        t << "`" << r.peer_timing << "` " << num(r.ms_per_image_mean, 2) << " ms/image mean, "
          << num(r.ms_per_image_median, 2) << " median; process " << num(r.process_wall_s, 1)
          << " s\n";
      else if (r.status == "ok")
        t << "no `ms/image` line in its log; process " << num(r.process_wall_s, 1) << " s\n";
      else
        t << r.status << (r.error.empty() ? "" : ": " + shorten(r.error, 300)) << "\n";
    }
  }
  return t.str();
}

}  // namespace

std::vector<std::pair<std::string, double>> readStages(const std::string& path) {
  std::vector<std::pair<std::string, double>> stages;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header: stage,total [s],calls,mean [ms]
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma == std::string::npos) continue;
    // "stage/part" rows break a stage down; the stage's own row already counts their time.
    if (line.substr(0, comma).find('/') != std::string::npos) continue;
    stages.emplace_back(line.substr(0, comma), std::atof(line.c_str() + comma + 1));
  }
  return stages;
}

bool readPeerTiming(const std::string& log_path, RunMetrics* m, std::size_t* images) {
  std::ifstream in(log_path);
  std::string line, timing;
  while (std::getline(in, line))
    if (line.find("ms/image") != std::string::npos) timing = line;
  if (timing.empty()) return false;
  m->ms_per_image_mean = numberAfter(timing, "mean");
  m->ms_per_image_median = numberAfter(timing, "median");
  const double n = numberAfter(timing, "images");
  *images = std::isfinite(n) && n > 0 ? static_cast<std::size_t>(n) : 0;
  std::istringstream words(timing.substr(0, timing.find("ms/image")));
  std::string w;
  m->peer_timing.clear();
  while (words >> w) m->peer_timing = w;  // the word before "ms/image"
  return std::isfinite(m->ms_per_image_mean);
}

std::string wallTimeFile(const RunJob& job) { return (fs::path(job.dir) / "wall_s.txt").string(); }

std::vector<RunMetrics> collectResults(const Matrix& matrix, const std::vector<RunJob>& jobs,
                                       const std::string& out_dir) {
  std::vector<RunMetrics> out;
  eval::EvaluationOptions options;
  options.alignment = matrix.alignment;
  for (const MatrixSequence& seq : matrix.sequences) {
    std::vector<const RunJob*> seq_jobs;
    for (const RunJob& j : jobs)
      if (j.sequence == seq.name) seq_jobs.push_back(&j);
    if (seq_jobs.empty()) continue;
    const std::string path = seq_jobs.front()->dataset;

    std::optional<eval::GroundTruth> gt;
    std::string gt_problem;
    if (!fs::exists(path)) {
      gt_problem = "sequence not found: " + path;
    } else {
      try {
        gt = run::loadRunGroundTruth(path, nullptr);
        if (!gt) gt_problem = "the sequence has no ground truth";
        if (gt && gt->trajectory.repeated_stamps > 0)
          std::cerr << "hdvio_bench: " << seq.name << ": " << eval::repeatedStampsWarning(gt->trajectory) << "\n";
      } catch (const std::exception& e) {
        gt_problem = std::string("ground truth: ") + e.what();
      }
    }
    eval::EvaluationReport report;
    report.ground_truth_source = path;
    report.options = options;
    if (gt) report.distances = eval::relativeErrorDistances(*gt, options);

    for (const RunJob* j : seq_jobs) {
      RunMetrics m;
      m.job = *j;
      if (!j->not_applicable.empty()) {
        m.status = "n/a";
        m.error = j->not_applicable;
        out.push_back(m);
        continue;
      }
      m.process_wall_s = readNumber(wallTimeFile(*j));
      if (!runCompleted(*j)) {
        if (fs::exists(j->log)) {
          m.status = "failed";
          m.error = lastErrorLine(j->log);
        }
        out.push_back(m);
        continue;
      }
      std::size_t peer_images = 0;
      if (j->peer()) {
        readPeerTiming(j->log, &m, &peer_images);
      } else {
        m.stages = readStages((fs::path(j->result_dir) / "timing_stages.csv").string());
        m.runtime_s = 0.0;
        for (const auto& s : m.stages) m.runtime_s += s.second;
        const std::vector<double> per_image =
            run::readImageProcessingMs((fs::path(j->result_dir) / "timing_images.csv").string());
        if (!per_image.empty()) {
          const run::TimeQuantiles q = run::timeQuantiles(per_image);
          m.ms_per_image_mean = q.mean;
          m.ms_per_image_median = q.p50;
          m.ms_per_image_p90 = q.p90;
          m.peer_timing = "frontend+backend";
        }
      }
      if (!gt) {
        m.status = "no_groundtruth";
        m.error = gt_problem;
        out.push_back(m);
        continue;
      }
      try {
        const eval::Estimate est = eval::loadEstimate(
            eval::resultFolderSpec(estimateName(*j), j->result_dir), eval::TrajectoryFormat::kAuto);
        // As hdvio_eval: repeated stamps are kept and associated one by one (evo's way), and said.
        if (est.trajectory.repeated_stamps > 0)
          std::cerr << "hdvio_bench: " << seq.name << "/" << j->experiment << ": "
                    << eval::repeatedStampsWarning(est.trajectory) << "\n";
        if (est.trajectory.size() > 1)
          m.duration_s = secondsBetween(est.trajectory.t.front(), est.trajectory.t.back());
        report.results.push_back(eval::evaluateEstimate(*gt, est, options, report.distances));
        fillMetrics(report.results.back(), &m);
        m.status = "ok";
        if (j->peer() && std::isfinite(m.ms_per_image_mean))  // one pose per image if not printed
          m.runtime_s = m.ms_per_image_mean * 1e-3 * (peer_images ? peer_images : m.poses);
        if (m.runtime_s > 0.0) m.realtime_factor = m.duration_s / m.runtime_s;
      } catch (const std::exception& e) {
        m.status = "failed";
        m.error = std::string("evaluation: ") + e.what();
      }
      out.push_back(m);
    }
    if (gt && !report.results.empty())
      eval::writeReport(report, *gt, (fs::path(out_dir) / "evaluation" / seq.name).string());
  }
  return out;
}

std::string writeBenchReport(const Matrix& matrix, const std::vector<RunMetrics>& runs,
                             const std::string& out_dir) {
  // Cells: (sequence, experiment) -> its runs (one per seed).
  std::map<std::pair<std::string, std::string>, std::vector<const RunMetrics*>> cells;
  std::vector<std::string> seqs, exps;
  for (const RunMetrics& r : runs) {
    cells[{r.job.sequence, r.job.experiment}].push_back(&r);
    if (std::find(seqs.begin(), seqs.end(), r.job.sequence) == seqs.end()) seqs.push_back(r.job.sequence);
  }
  std::vector<std::string> columns;  // the experiments, then the peers
  for (const auto& e : matrix.experiments)
    if (std::find(columns.begin(), columns.end(), e.name) == columns.end()) columns.push_back(e.name);
  for (const auto& p : matrix.peers) columns.push_back(p.name);
  for (const auto& name : columns)
    for (const RunMetrics& r : runs)
      if (r.job.experiment == name) {
        exps.push_back(name);
        break;
      }
  std::map<std::string, int> counts;
  bool any_force = false;
  std::vector<std::string> stage_names;
  for (const RunMetrics& r : runs) {
    ++counts[r.status];
    any_force = any_force || std::isfinite(r.force_total_rmse);
    for (const auto& s : r.stages)
      if (std::find(stage_names.begin(), stage_names.end(), s.first) == stage_names.end())
        stage_names.push_back(s.first);
  }

  auto grid = [&](const std::string& title, const std::function<std::string(const std::vector<const RunMetrics*>&)>& cell) {
    std::ostringstream t;
    t << "\n### " << title << "\n\n| sequence |";
    for (const auto& e : exps) t << " " << e << " |";
    t << "\n|---|";
    for (std::size_t i = 0; i < exps.size(); ++i) t << "---|";
    t << "\n";
    for (const auto& s : seqs) {
      t << "| " << s << " |";
      for (const auto& e : exps) t << " " << cell(cells[{s, e}]) << " |";
      t << "\n";
    }
    return t.str();
  };
  // A cell's text when no run of it completed, else the mean over its seeds and a note.
  auto status = [](const std::vector<const RunMetrics*>& rs, std::string* text) {
    int ok = 0, bad = 0;
    for (const RunMetrics* r : rs) (r->status == "ok" ? ok : bad)++;
    if (ok == 0) {
      if (rs.empty()) *text = "-";
      else if (rs.front()->status == "n/a") *text = "n/a";
      else if (rs.front()->error.empty()) *text = rs.front()->status;
      else *text = rs.front()->status + ": " + markdownCell(shorten(rs.front()->error, 70));
      return false;
    }
    *text = rs.size() > 1 ? " (" + std::to_string(ok) + " seeds" +
                                (bad ? ", " + std::to_string(bad) + " not ok" : "") + ")"
                          : "";
    return true;
  };

  std::ostringstream t;
  t << "## hdvio_bench: " << matrix.file << "\n\n"
    << "Alignment: " << eval::alignmentName(matrix.alignment)
    << ". Runs: " << runs.size();
  for (const auto& c : counts) t << ", " << c.second << " " << c.first;
  t << (matrix.seeds.empty() ? "" : ". Cells are means over seeds") << ".\n";
  t << grid("ATE_T [m] / ATE_R [deg] (rmse)", [&](const auto& rs) {
    std::string note;
    if (!status(rs, &note)) return note;
    return num(cellMean(rs, &RunMetrics::ate_t_m), 3) + " / " +
           num(cellMean(rs, &RunMetrics::ate_r_deg), 2) + note;
  });
  if (any_force)
    t << grid("Force RMSE [m/s^2]: total non-thrust force / external force", [&](const auto& rs) {
      std::string note;
      if (!status(rs, &note)) return note;
      return num(cellMean(rs, &RunMetrics::force_total_rmse), 3) + " / " +
             num(cellMean(rs, &RunMetrics::force_external_rmse), 3) + note;
    });
  t << grid("Runtime: summed stage time [s] (x faster than real time); per image [ms]: mean "
            "(p90) of frontend + backend, or what a peer prints", [&](const auto& rs) {
    std::string note;
    if (!status(rs, &note)) return note;
    if (rs.front()->job.peer() && !std::isfinite(rs.front()->ms_per_image_mean))
      return std::string("no time printed");
    std::string cell = num(cellMean(rs, &RunMetrics::runtime_s), 2) + " (" +
                       num(cellMean(rs, &RunMetrics::realtime_factor), 1) + "x)" + note;
    if (std::isfinite(rs.front()->ms_per_image_mean)) {
      cell += "; " + num(cellMean(rs, &RunMetrics::ms_per_image_mean), 2) + " ms/image";
      if (std::isfinite(rs.front()->ms_per_image_p90))
        cell += " (p90 " + num(cellMean(rs, &RunMetrics::ms_per_image_p90), 2) + ")";
    }
    return cell;
  });
  if (!matrix.peers.empty()) t << peerNotes(matrix, runs);
  if (!stage_names.empty()) {
    t << "\n### Wall time per stage [s]\n\n| run |";
    for (const auto& s : stage_names) t << " " << s << " |";
    t << " process [s] |\n|---|";
    for (std::size_t i = 0; i <= stage_names.size(); ++i) t << "---|";
    t << "\n";
    for (const RunMetrics& r : runs) {
      if (r.stages.empty()) continue;
      t << "| " << r.job.label << " |";
      for (const auto& name : stage_names) {
        double v = NAN;
        for (const auto& s : r.stages)
          if (s.first == name) v = s.second;
        t << " " << num(v, 2) << " |";
      }
      t << " " << num(r.process_wall_s, 1) << " |\n";
    }
  }
  bool any_problem = false;
  for (const RunMetrics& r : runs)
    if (r.status != "ok" && !r.job.peer()) {  // peers: in the peer notes above
      if (!any_problem) t << "\n### Runs without numbers\n\n";
      any_problem = true;
      t << "- " << r.job.label << ": " << r.status
        << (r.error.empty() ? "" : ": " + shorten(r.error, 300)) << " (log: " << r.job.log << ")\n";
    }

  std::ostringstream csv;
  csv << "sequence,experiment,seed,status,ate_t_m,ate_r_deg,rpe_t_m,velocity_rmse_m_s,"
         "force_total_rmse_m_s2,force_external_rmse_m_s2,matched,poses,runtime_s,duration_s,"
         "realtime_factor,process_wall_s,result_dir,error,peer,ms_per_image_mean,"
         "ms_per_image_median,peer_timing,ms_per_image_p90\n";
  Json json_runs = Json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunMetrics& r = runs[i];
    const std::string seed = r.job.seed ? std::to_string(*r.job.seed) : "";
    csv << r.job.sequence << "," << r.job.experiment << "," << seed << "," << r.status << ","
        << full(r.ate_t_m, "") << "," << full(r.ate_r_deg, "") << "," << full(r.rpe_t_m, "") << ","
        << full(r.velocity_rmse, "") << "," << full(r.force_total_rmse, "") << ","
        << full(r.force_external_rmse, "") << "," << r.matched << "," << r.poses << ","
        << full(r.runtime_s, "") << "," << full(r.duration_s, "") << ","
        << full(r.realtime_factor, "") << "," << full(r.process_wall_s, "") << ","
        << csvField(r.job.result_dir) << "," << csvField(r.error) << ","
        << (r.job.peer() ? "true" : "false") << "," << full(r.ms_per_image_mean, "") << ","
        << full(r.ms_per_image_median, "") << "," << csvField(r.peer_timing) << ","
        << full(r.ms_per_image_p90, "") << "\n";
    json_runs.push_back(runJson(r));
  }

  std::error_code ec;
  fs::create_directories(out_dir, ec);
  eval::writeFileAtomically((fs::path(out_dir) / "table.md").string(), t.str());
  eval::writeFileAtomically((fs::path(out_dir) / "results.csv").string(), csv.str());
  const Json json = {{"matrix", matrix.file},
                     {"alignment", eval::alignmentName(matrix.alignment)},
                     {"runs", json_runs}};
  // replace: an error line or path with invalid UTF-8 must not lose the whole report.
  eval::writeFileAtomically((fs::path(out_dir) / "results.json").string(),
                            json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
  return t.str();
}

}  // namespace hdvio::bench
