// hdvio_bench: a matrix of experiments x sequences (x seeds), each run as its own hdvio_run
// process (--jobs in parallel), evaluated into one table like the papers' (docs/bench.md).
//   hdvio_bench --matrix config/bench/sim_drag.yaml --out results/sim_drag --jobs 2
//   hdvio_bench --matrix ... --out ... --emit-jobs jobs.txt    # for GNU parallel / job arrays
#include <gflags/gflags.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>

#include "hdvio/bench/aggregate.h"
#include "hdvio/bench/compare.h"
#include "hdvio/bench/matrix.h"
#include "hdvio/bench/process_pool.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/eval/report.h"
#include "hdvio/run/run_evaluation.h"

DEFINE_string(matrix, "", "benchmark matrix YAML (config/bench/)");
DEFINE_string(out, "", "output folder: sequences/, runs/, evaluation/, table.md, results.*");
DEFINE_int32(jobs, 1, "processes run in parallel");
DEFINE_string(emit_jobs, "", "write the commands (one per line) to this file ('-': stdout) and exit");
DEFINE_string(only, "", "only runs whose '<sequence>/<experiment>[/seed<k>]' contains this");
DEFINE_bool(force, false, "rerun runs that already completed");
DEFINE_bool(aggregate_only, false, "run nothing; evaluate the runs present and write the table");
DEFINE_string(hdvio_run, "", "hdvio_run binary (default: next to hdvio_bench, else the build tree's)");
DEFINE_string(hdvio_sim, "", "hdvio_sim binary (default: next to hdvio_bench, else the build tree's)");
DEFINE_string(hdvio_image_noise, "", "hdvio_image_noise binary, for peers over noise seeds (default: next to hdvio_bench, else the build tree's)");
DEFINE_string(compare, "", "run nothing; compare the runs of this earlier output folder with --out's, seed means per experiment and sequence");
DEFINE_string(metric, "ate_t_m", "with --compare: a numeric field of results.json's runs (ate_t_m, rpe_t_m, ms_per_image_mean, ...)");
DEFINE_string(python, "/usr/bin/python3", "python interpreter for the figures and for indsim sequences");

namespace hdvio::bench {
namespace {
namespace fs = std::filesystem;

fs::path selfPath() {
  std::error_code ec;
  return fs::read_symlink("/proc/self/exe", ec);
}

std::string findTool(const std::string& flag_value, const std::string& name,
                     const std::string& build_tree_path) {
  std::error_code ec;
  if (!flag_value.empty()) {
    if (!fs::exists(flag_value, ec)) throw InputError("--" + name, 0, "no such file: " + flag_value);
    return fs::absolute(flag_value).string();
  }
  const fs::path next_to_me = selfPath().parent_path() / name;
  if (fs::exists(next_to_me, ec)) return next_to_me.string();
  if (fs::exists(build_tree_path, ec)) return build_tree_path;
  throw InputError("--" + name, 0, name + " not found next to hdvio_bench nor at " + build_tree_path);
}

std::string benchPlotScript() {
  std::error_code ec;
  const fs::path next_to_me = selfPath().parent_path() / "plot_bench.py";
  if (fs::exists(next_to_me, ec)) return next_to_me.string();
  return HDVIO_BENCH_PLOT_SCRIPT;
}

Command simCommand(const MatrixSequence& q, const std::string& sim, const std::string& out_dir) {
  Command c;
  c.label = "sequence " + q.name;
  if (q.source == MatrixSequence::Source::kIndsim) {
    // Written beside the folder and renamed at the end: a folder that exists is complete (it
    // is reused), whatever stopped a render. Without images, indsim still writes cam0's
    // calibration and image list: removed, as its make_flights.sh does.
    c.argv = {"/bin/sh", "-c",
              "rm -rf \"$3.partial\" && \"$0\" \"$1\" --config \"$2\" --out \"$3.partial\" $4 && "
              "{ [ -z \"$4\" ] || rm -rf \"$3.partial/mav0/cam0\"; } && mv \"$3.partial\" \"$3\"",
              FLAGS_python, indsimScript(q), q.sim_config, sequencePath(q, out_dir),
              q.sim_images ? "" : "--no-images"};
  } else {
    c.argv = {sim, "--config", q.sim_config, "--out", sequencePath(q, out_dir)};
    if (!q.sim_images) c.argv.push_back("--no_images");
  }
  c.log = (fs::absolute(out_dir) / "sequences" / (q.name + ".log")).lexically_normal().string();
  return c;
}

// The noisy copy of a sequence that a seeded peer reads (its images with that seed's noise).
Command noisyCopyCommand(const Matrix& m, const RunJob& j, const std::string& tool) {
  std::ostringstream sigma;
  sigma << std::setprecision(17) << m.image_noise_sigma;  // the matrix's value, not a rounding
  return {"sequence " + fs::path(j.dataset).filename().string(),
          {tool, "--dataset", j.noisy_copy_of, "--sigma", sigma.str(), "--seed",
           std::to_string(*j.seed), "--out", j.dataset},
          j.dataset + ".log"};
}

// One command per noisy copy still to write (several peers may read the same copy).
std::vector<Command> noisyCopyCommands(const Matrix& m, const std::vector<RunJob>& jobs,
                                       const std::string& tool) {
  std::vector<Command> commands;
  std::set<std::string> seen;
  std::error_code ec;
  for (const RunJob& j : jobs)
    if (!j.noisy_copy_of.empty() && j.not_applicable.empty() && !fs::exists(j.dataset, ec) &&
        seen.insert(j.dataset).second)
      commands.push_back(noisyCopyCommand(m, j, tool));
  return commands;
}

Command runCommand(const RunJob& j, const std::string& run) {
  // A peer writes a partial estimate that finishPeerRun (or the emitted line) moves into result/.
  if (j.peer()) return {j.label, {j.peer_command, j.dataset, peerPartialEstimate(j)}, j.log};
  // Each run evaluates itself (result/evaluation/) without figures; the bench draws its own.
  return {j.label, {run, "--config", j.config, "--dataset", j.dataset, "--out", j.result_dir,
                    "--plots=false"}, j.log};
}

// The emitted shell line of a run: a peer's also moves its estimate into place on success.
std::string runShellLine(const RunJob& j, const std::string& run) {
  std::string line = shellLine(runCommand(j, run));
  if (j.peer())
    line += " && mkdir -p " + shellQuote(j.result_dir) + " && mv " +
            shellQuote(peerPartialEstimate(j)) + " " + shellQuote(peerEstimate(j));
  return line;
}

// Whether a sequence is read by any job that will run (not the peers' "n/a" cells).
bool sequenceUsed(const MatrixSequence& q, const std::vector<RunJob>& jobs) {
  for (const auto& j : jobs)
    if (j.sequence == q.name && j.not_applicable.empty()) return true;
  return false;
}

bool pythonHasMatplotlib() {
  const std::string check = "'" + FLAGS_python + "' -c 'import matplotlib, numpy' > /dev/null 2>&1";
  return std::system(check.c_str()) == 0;
}

void drawFigures(const Matrix& matrix, const std::string& out_dir) {
  if (!matrix.plots) return;
  if (!pythonHasMatplotlib()) {
    std::fprintf(stderr, "hdvio_bench: note: figures skipped, %s with matplotlib and numpy is "
                         "needed (Debian: python3-matplotlib)\n", FLAGS_python.c_str());
    return;
  }
  std::vector<std::string> commands;
  commands.push_back("'" + FLAGS_python + "' '" + benchPlotScript() + "' --dir '" + out_dir + "'");
  const std::string eval_script = run::findEvalPlotScript();
  std::error_code ec;
  for (const auto& q : matrix.sequences) {
    const fs::path d = fs::path(out_dir) / "evaluation" / q.name;
    if (!eval_script.empty() && fs::exists(d / "metrics.json", ec))
      commands.push_back("'" + FLAGS_python + "' '" + eval_script + "' --dir '" + d.string() + "'");
  }
  for (const auto& cmd : commands)
    if (std::system((cmd + " > /dev/null").c_str()) != 0)
      std::fprintf(stderr, "hdvio_bench: note: plotting failed: %s\n", cmd.c_str());
}

int emitJobs(const Matrix& matrix, const std::vector<RunJob>& jobs, const std::string& out_dir,
             const std::string& run, const std::string& sim, const std::string& noise) {
  std::ostringstream o;
  o << "# hdvio_bench jobs for " << matrix.file << ": run phase 1 first, then the lines of phase 2\n"
    << "# in any order or in parallel, then phase 3. Each line is independent.\n";
  o << "# phase 1: sequences\n";
  fs::create_directories(fs::path(out_dir) / "sequences");
  for (const auto& q : matrix.sequences)
    if (sequenceUsed(q, jobs) && q.simulated() && !fs::exists(sequencePath(q, out_dir)))
      o << shellLine(simCommand(q, sim, out_dir)) << "\n";
  const std::vector<Command> copies = noisyCopyCommands(matrix, jobs, noise);
  if (!copies.empty()) o << "# phase 1b (after phase 1): the peers' noisy copies of the sequences\n";
  for (const auto& c : copies) o << shellLine(c) << "\n";
  o << "# phase 2: runs\n";
  for (const auto& j : jobs) {
    if (!j.not_applicable.empty()) continue;
    prepareJobConfig(matrix, j);
    o << runShellLine(j, run) << "\n";
  }
  o << "# phase 3: aggregate\n"
    << shellLine({"", {selfPath().string(), "--matrix", matrix.file, "--out",
                       fs::absolute(out_dir).lexically_normal().string(), "--aggregate_only"}, ""})
    << "\n";
  if (FLAGS_emit_jobs == "-") {
    std::cout << o.str();
  } else {
    eval::writeFileAtomically(FLAGS_emit_jobs, o.str());
    std::fprintf(stderr, "hdvio_bench: %zu runs written to %s\n", jobs.size(), FLAGS_emit_jobs.c_str());
  }
  return 0;
}

void generateSequences(const Matrix& matrix, const std::vector<RunJob>& jobs,
                       const std::string& out_dir, const std::string& sim) {
  std::vector<Command> commands;
  for (const auto& q : matrix.sequences)
    if (sequenceUsed(q, jobs) && q.simulated() && !fs::exists(sequencePath(q, out_dir)))
      commands.push_back(simCommand(q, sim, out_dir));
  if (commands.empty()) return;
  fs::create_directories(fs::path(out_dir) / "sequences");
  runCommands(commands, FLAGS_jobs, [&](std::size_t i, const CommandOutcome& o) {
    if (o.exit_code == 0)
      std::fprintf(stderr, "hdvio_bench: %s generated (%.1f s)\n", commands[i].label.c_str(), o.wall_s);
    else  // its runs then fail with "sequence not found", reported in the table
      std::fprintf(stderr, "hdvio_bench: %s FAILED (exit %d): %s\n", commands[i].label.c_str(),
                   o.exit_code, lastErrorLine(commands[i].log).c_str());
  });
}

void writeNoisyCopies(const Matrix& matrix, const std::vector<RunJob>& jobs,
                      const std::string& tool) {
  const std::vector<Command> commands = noisyCopyCommands(matrix, jobs, tool);
  for (const Command& c : commands) fs::create_directories(fs::path(c.log).parent_path());
  runCommands(commands, FLAGS_jobs, [&](std::size_t i, const CommandOutcome& o) {
    if (o.exit_code == 0)
      std::fprintf(stderr, "hdvio_bench: %s written (%.1f s)\n", commands[i].label.c_str(), o.wall_s);
    else  // the peer's run then fails on the missing folder, reported in the table
      std::fprintf(stderr, "hdvio_bench: %s FAILED (exit %d): %s\n", commands[i].label.c_str(),
                   o.exit_code, lastErrorLine(commands[i].log).c_str());
  });
}

void runJobs(const Matrix& matrix, const std::vector<RunJob>& jobs, const std::string& run) {
  std::vector<Command> commands;
  std::vector<const RunJob*> pending;
  std::size_t not_applicable = 0, missing_peers = 0;
  for (const auto& j : jobs) {
    if (!j.not_applicable.empty()) {
      ++not_applicable;
      continue;
    }
    if (!FLAGS_force && runCompleted(j)) continue;
    prepareJobConfig(matrix, j);
    std::error_code ec;
    fs::remove(wallTimeFile(j), ec);
    if (j.peer()) {  // a rerun must not leave the previous estimate looking complete
      fs::remove_all(j.result_dir, ec);
      fs::remove(peerPartialEstimate(j), ec);
      if (!fs::exists(j.peer_command, ec)) {  // recorded like a failed run, nothing started
        std::ofstream(j.log) << "error: peer command not found: " << j.peer_command << "\n";
        std::fprintf(stderr, "hdvio_bench: %s: peer command not found: %s\n", j.label.c_str(),
                     j.peer_command.c_str());
        ++missing_peers;
        continue;
      }
    }
    commands.push_back(runCommand(j, run));
    pending.push_back(&j);
  }
  const std::size_t todo = commands.size() + missing_peers;
  std::fprintf(stderr, "hdvio_bench: %zu runs to do, %zu already complete, %d in parallel\n", todo,
               jobs.size() - todo - not_applicable, FLAGS_jobs);
  std::size_t finished = 0;
  runCommands(commands, FLAGS_jobs, [&](std::size_t i, const CommandOutcome& o) {
    ++finished;
    if (o.exit_code == 0 && (!pending[i]->peer() || finishPeerRun(*pending[i]))) {
      eval::writeFileAtomically(wallTimeFile(*pending[i]), std::to_string(o.wall_s) + "\n");
      std::fprintf(stderr, "hdvio_bench: [%zu/%zu] %s ok (%.1f s)\n", finished, commands.size(),
                   commands[i].label.c_str(), o.wall_s);
    } else {
      std::fprintf(stderr, "hdvio_bench: [%zu/%zu] %s FAILED (exit %d): %s\n", finished,
                   commands.size(), commands[i].label.c_str(), o.exit_code,
                   lastErrorLine(commands[i].log).c_str());
    }
  });
}

int compareMain() {
  if (FLAGS_out.empty()) throw InputError("--out", 0, "--compare needs --out: the later output folder");
  if (!FLAGS_matrix.empty())
    throw InputError("--matrix", 0, "--compare runs nothing: run the matrix first, then compare");
  const Comparison c = compareRuns(readRunValues(FLAGS_compare, FLAGS_metric),
                                   readRunValues(FLAGS_out, FLAGS_metric));
  std::cout << comparisonMarkdown(c, FLAGS_metric, FLAGS_compare, FLAGS_out) << std::flush;
  return 0;
}

int benchMain() {
  if (!FLAGS_compare.empty()) return compareMain();
  if (FLAGS_matrix.empty() || FLAGS_out.empty())
    throw InputError("", 0, "usage: hdvio_bench --matrix <yaml> --out <dir> [--jobs N] "
                            "[--emit-jobs <file>|-] [--only <substring>] [--force]");
  if (FLAGS_jobs < 1) throw InputError("--jobs", 0, "must be at least 1");
  const Matrix matrix = loadMatrix(FLAGS_matrix);
  const std::string out_dir = fs::absolute(FLAGS_out).lexically_normal().string();
  const std::vector<RunJob> jobs = expandJobs(matrix, out_dir, FLAGS_only);
  if (jobs.empty()) throw InputError("--only", 0, "no run matches '" + FLAGS_only + "'");

  if (!FLAGS_aggregate_only) {
    const std::string run = findTool(FLAGS_hdvio_run, "hdvio_run", HDVIO_BENCH_RUN_BINARY);
    bool any_sim = false;
    for (const auto& q : matrix.sequences)
      any_sim = any_sim || q.source == MatrixSequence::Source::kHdvioSim;
    const std::string sim =
        any_sim ? findTool(FLAGS_hdvio_sim, "hdvio_sim", HDVIO_BENCH_SIM_BINARY) : "";
    bool any_noisy = false;
    for (const auto& j : jobs) any_noisy = any_noisy || !j.noisy_copy_of.empty();
    const std::string noise = any_noisy ? findTool(FLAGS_hdvio_image_noise, "hdvio_image_noise",
                                                   HDVIO_BENCH_NOISE_BINARY)
                                        : "";
    if (!FLAGS_emit_jobs.empty()) return emitJobs(matrix, jobs, out_dir, run, sim, noise);
    generateSequences(matrix, jobs, out_dir, sim);
    writeNoisyCopies(matrix, jobs, noise);
    runJobs(matrix, jobs, run);
  }

  const std::vector<RunMetrics> results = collectResults(matrix, jobs, out_dir);
  std::cout << writeBenchReport(matrix, results, out_dir) << std::flush;
  drawFigures(matrix, out_dir);
  // Peers are outside the project: one that is not built or fails is a note in its cells,
  // not a failure of the benchmark. "n/a" cells (a peer on a sequence without images) neither.
  int not_ok = 0, peers_not_ok = 0;
  for (const auto& r : results) {
    if (r.status == "ok" || r.status == "n/a") continue;
    ++(r.job.peer() ? peers_not_ok : not_ok);
  }
  if (peers_not_ok)
    std::fprintf(stderr, "hdvio_bench: note: %d peer runs have no numbers (listed in the table)\n",
                 peers_not_ok);
  std::fprintf(stderr, "hdvio_bench: table in %s/table.md%s\n", out_dir.c_str(),
               not_ok ? "; some runs have no numbers (listed in the table), exit 1" : "");
  return not_ok ? 1 : 0;
}

}  // namespace
}  // namespace hdvio::bench

int main(int argc, char** argv) {
  // Accept --emit-jobs and --aggregate-only spellings: gflags names use underscores.
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--", 2) != 0) continue;
    for (char* c = argv[i] + 2; *c && *c != '='; ++c)
      if (*c == '-') *c = '_';
  }
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_bench --matrix <yaml> --out <dir> [--jobs N] [--emit-jobs <file>|-] [--only <substring>]\n"
      "       hdvio_bench --compare <earlier out dir> --out <dir> [--metric ate_t_m]\n"
      "runs a matrix of experiments x sequences (x seeds) and evaluates it into one table\n"
      "example: hdvio_bench --matrix config/bench/ci_tiny.yaml --out /tmp/bench_tiny --jobs 2");
  return hdvio::runTool(hdvio::bench::benchMain);
}
