#include "hdvio/bench/matrix.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/eval/report.h"

namespace hdvio::bench {
namespace fs = std::filesystem;

namespace {

// The raw document, only for line numbers of problems ConfigReader cannot see (missing files).
long lineOf(const YAML::Node& root, const std::string& list, std::size_t index,
            const std::string& key) {
  try {
    const YAML::Node n = root[list][index][key];
    if (n.IsDefined()) return n.Mark().line + 1;
  } catch (const YAML::Exception&) {
  }
  return 0;
}

void checkName(const std::string& file, long line, const std::string& what,
               const std::string& name, std::set<std::string>* seen) {
  bool ok = !name.empty();
  for (char c : name)
    ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  if (!ok)
    throw InputError(file, line, what + " name '" + name + "': use letters, digits, _ - . only");
  if (!seen->insert(name).second)
    throw InputError(file, line, what + " name '" + name + "' appears twice");
}

std::string resolve(const fs::path& base, const std::string& path) {
  const fs::path p(path);
  return (p.is_absolute() ? p : base / p).lexically_normal().string();
}

void requireExists(const std::string& file, long line, const std::string& key,
                   const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw InputError(file, line, "key '" + key + "': no such file or folder: " + path);
}

// Relative strings that name an existing file next to the original experiment become absolute.
void absolutizePaths(YAML::Node node, const fs::path& base) {
  if (node.IsMap()) {
    for (auto kv : node) absolutizePaths(kv.second, base);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) absolutizePaths(node[i], base);
  } else if (node.IsScalar()) {
    const std::string s = node.Scalar();
    std::error_code ec;
    if (!s.empty() && fs::path(s).is_relative() && fs::exists(base / s, ec))
      node = (base / s).lexically_normal().string();
  }
}

}  // namespace

Matrix loadMatrix(const std::string& path) {
  const ConfigReader cfg = ConfigReader::fromFile(path);
  const YAML::Node raw = YAML::LoadFile(path);  // ConfigReader parsed it already
  const fs::path base = fs::absolute(path).parent_path();
  Matrix m;
  m.file = fs::absolute(path).lexically_normal().string();

  std::set<std::string> names;
  const std::vector<ConfigReader> experiments = cfg.list("experiments");
  for (std::size_t i = 0; i < experiments.size(); ++i) {
    const ConfigReader& e = experiments[i];
    MatrixExperiment x;
    e.read("name", &x.name);
    std::string config;
    e.read("config", &config);
    e.readOptional("sequences", &x.sequences);
    e.finish();
    // A name may repeat when each entry lists its sequences: one column, a config per group.
    const auto same = std::find_if(m.experiments.begin(), m.experiments.end(),
                                   [&](const MatrixExperiment& o) { return o.name == x.name; });
    if (same == m.experiments.end() || x.sequences.empty() || same->sequences.empty())
      checkName(path, lineOf(raw, "experiments", i, "name"), "experiment", x.name, &names);
    x.config = resolve(base, config);
    requireExists(path, lineOf(raw, "experiments", i, "config"), e.path() + ".config", x.config);
    m.experiments.push_back(x);
  }
  if (cfg.has("peers")) {
    const std::vector<ConfigReader> peers = cfg.list("peers");
    for (std::size_t i = 0; i < peers.size(); ++i) {
      MatrixPeer p;
      peers[i].read("name", &p.name);
      std::string command;
      peers[i].read("command", &command);
      peers[i].finish();
      checkName(path, lineOf(raw, "peers", i, "name"), "peer", p.name, &names);
      if (command.empty())
        throw InputError(path, lineOf(raw, "peers", i, "command"),
                         "key '" + peers[i].path() + ".command': empty");
      p.command = resolve(base, command);  // may be absent: the peer's cells then say so
      m.peers.push_back(p);
    }
  }

  names.clear();
  const std::vector<ConfigReader> sequences = cfg.list("sequences");
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const ConfigReader& s = sequences[i];
    MatrixSequence q;
    s.read("name", &q.name);
    std::string dataset, sim, indsim;
    s.readOptional("dataset", &dataset);
    s.readOptional("sim", &sim);
    s.readOptional("indsim", &indsim);
    if (s.has("sim") || s.has("indsim")) s.readOptional("images", &q.sim_images);
    s.finish();  // `images` with `dataset` is an unknown key
    checkName(path, lineOf(raw, "sequences", i, "name"), "sequence", q.name, &names);
    if (int(!dataset.empty()) + int(!sim.empty()) + int(!indsim.empty()) != 1)
      throw InputError(path, lineOf(raw, "sequences", i, "name"),
                       "key '" + s.path() + "': give exactly one of 'dataset', 'sim' and 'indsim'");
    if (!dataset.empty()) {
      q.dataset = resolve(base, dataset);
      requireExists(path, lineOf(raw, "sequences", i, "dataset"), s.path() + ".dataset", q.dataset);
    } else if (!sim.empty()) {
      q.source = MatrixSequence::Source::kHdvioSim;
      q.sim_config = resolve(base, sim);
      requireExists(path, lineOf(raw, "sequences", i, "sim"), s.path() + ".sim", q.sim_config);
    } else {
      q.source = MatrixSequence::Source::kIndsim;
      q.sim_config = resolve(base, indsim);
      requireExists(path, lineOf(raw, "sequences", i, "indsim"), s.path() + ".indsim", q.sim_config);
      const std::string script = indsimScript(q);
      requireExists(path, lineOf(raw, "sequences", i, "indsim"), s.path() + ".indsim (its simulator)", script);
    }
    m.sequences.push_back(q);
  }
  if (m.experiments.empty()) throw InputError(path, 0, "key 'experiments': the list is empty");
  for (std::size_t i = 0; i < m.experiments.size(); ++i) {
    const MatrixExperiment& x = m.experiments[i];
    for (const std::string& s : x.sequences) {
      const long line = lineOf(raw, "experiments", i, "sequences");
      if (std::none_of(m.sequences.begin(), m.sequences.end(),
                       [&](const MatrixSequence& q) { return q.name == s; }))
        throw InputError(path, line, "key '" + experiments[i].path() + ".sequences': no sequence '" + s + "'");
      for (std::size_t k = 0; k < i; ++k)
        if (m.experiments[k].name == x.name && m.experiments[k].runsOn(s))
          throw InputError(path, line, "experiment '" + x.name + "' runs twice on sequence '" + s + "'");
    }
  }
  if (m.sequences.empty()) throw InputError(path, 0, "key 'sequences': the list is empty");

  cfg.readOptional("seeds", &m.seeds);
  std::set<int> seeds;
  for (int s : m.seeds)
    if (s < 0 || !seeds.insert(s).second)
      throw InputError(path, raw["seeds"].Mark().line + 1,
                       "key 'seeds': seeds must be distinct and non-negative");
  cfg.readInRange("image_noise_sigma", &m.image_noise_sigma, 0.0, 50.0);
  if (m.image_noise_sigma > 0.0 && m.seeds.empty())
    throw InputError(path, raw["image_noise_sigma"].Mark().line + 1,
                     "key 'image_noise_sigma': needs 'seeds' (it varies with the seed)");

  const ConfigReader metrics = cfg.optionalSection("metrics");
  std::string alignment = "posyaw";
  metrics.readChoice("alignment", &alignment, {"none", "posyaw", "se3", "sim3"});
  m.alignment = eval::parseAlignmentType(alignment);
  metrics.readOptional("plots", &m.plots);
  metrics.finish();
  cfg.finish();
  return m;
}

bool MatrixExperiment::runsOn(const std::string& sequence) const {
  return sequences.empty() || std::find(sequences.begin(), sequences.end(), sequence) != sequences.end();
}

std::string indsimScript(const MatrixSequence& seq) {
  return (fs::path(seq.sim_config).parent_path().parent_path() / "indsim.py").lexically_normal().string();
}

std::string sequencePath(const MatrixSequence& seq, const std::string& out_dir) {
  if (!seq.simulated()) return seq.dataset;
  return (fs::absolute(out_dir) / "sequences" / seq.name).lexically_normal().string();
}

namespace {

// Why a peer (which reads an ASL folder's cam0 images) cannot run on a sequence, or "".
std::string peerNotApplicable(const MatrixSequence& q) {
  if (q.simulated())
    return q.sim_images ? "" : "the sequence is generated without images (images: false)";
  std::error_code ec;
  if (!fs::is_directory(fs::path(q.dataset) / "mav0" / "cam0" / "data", ec))
    return "not an ASL folder with images (no mav0/cam0/data)";
  return "";
}

}  // namespace

std::vector<RunJob> expandJobs(const Matrix& matrix, const std::string& out_dir,
                               const std::string& only) {
  std::vector<RunJob> jobs;
  const fs::path runs = fs::absolute(out_dir).lexically_normal() / "runs";
  std::vector<std::optional<int>> seeds;
  for (int s : matrix.seeds) seeds.push_back(s);
  if (seeds.empty()) seeds.push_back(std::nullopt);
  for (const MatrixSequence& q : matrix.sequences) {
    for (const MatrixExperiment& e : matrix.experiments)
      for (const auto& seed : e.runsOn(q.name) ? seeds : std::vector<std::optional<int>>{}) {
        RunJob j;
        j.sequence = q.name;
        j.experiment = e.name;
        j.seed = seed;
        fs::path dir = runs / q.name / e.name;
        j.label = q.name + "/" + e.name;
        if (seed) {
          dir /= "seed" + std::to_string(*seed);
          j.label += "/seed" + std::to_string(*seed);
        }
        if (!only.empty() && j.label.find(only) == std::string::npos) continue;
        j.dataset = sequencePath(q, out_dir);
        j.dir = dir.string();
        j.result_dir = (dir / "result").string();
        j.log = (dir / "log.txt").string();
        j.config = seed ? (dir / "experiment.yaml").string() : e.config;
        j.original_config = e.config;
        jobs.push_back(j);
      }
    // A peer reads the image files: it differs by seed only when the seed's noise is in them.
    const bool noisy_peers = matrix.image_noise_sigma > 0.0 && !matrix.seeds.empty();
    for (const MatrixPeer& p : matrix.peers)
      for (const auto& seed : noisy_peers ? seeds : std::vector<std::optional<int>>{std::nullopt}) {
        RunJob j;
        j.sequence = q.name;
        j.experiment = p.name;
        j.seed = seed;
        fs::path dir = runs / q.name / p.name;
        j.label = q.name + "/" + p.name;
        j.dataset = sequencePath(q, out_dir);
        if (seed) {
          dir /= "seed" + std::to_string(*seed);
          j.label += "/seed" + std::to_string(*seed);
          j.noisy_copy_of = j.dataset;
          j.dataset = (fs::absolute(out_dir).lexically_normal() / "sequences" /
                       (q.name + ".noise_seed" + std::to_string(*seed))).string();
        }
        if (!only.empty() && j.label.find(only) == std::string::npos) continue;
        j.dir = dir.string();
        j.result_dir = (dir / "result").string();
        j.log = (dir / "log.txt").string();
        j.peer_command = p.command;
        j.not_applicable = peerNotApplicable(q);
        jobs.push_back(j);
      }
  }
  return jobs;
}

void prepareJobConfig(const Matrix& matrix, const RunJob& job) {
  std::error_code ec;
  fs::create_directories(job.dir, ec);
  if (ec) throw InputError(job.dir, 0, "cannot create folder: " + ec.message());
  if (!job.seed || job.peer()) return;
  const std::string& original = job.original_config;
  YAML::Node doc = YAML::LoadFile(original);
  absolutizePaths(doc, fs::path(original).parent_path());
  doc["run"]["seed"] = *job.seed;
  std::string what = "run.seed = " + std::to_string(*job.seed);
  if (matrix.image_noise_sigma > 0.0) {
    doc["run"]["image_noise_sigma"] = matrix.image_noise_sigma;
    std::ostringstream sigma;
    sigma << matrix.image_noise_sigma;
    what += ", run.image_noise_sigma = " + sigma.str();
  }
  YAML::Emitter out;
  out << doc;
  eval::writeFileAtomically(job.config, "# " + original + " with " + what + " (hdvio_bench)\n" +
                                            out.c_str() + "\n");
}

bool runCompleted(const RunJob& job) {
  std::error_code ec;
  if (job.peer()) return fs::exists(peerEstimate(job), ec);
  const fs::path r(job.result_dir);
  return fs::exists(r / "stamped_traj_estimate.txt", ec) && fs::exists(r / "config.yaml", ec) &&
         fs::exists(r / "timing_stages.csv", ec);
}

std::string peerPartialEstimate(const RunJob& job) {
  return (fs::path(job.dir) / "estimate.partial.txt").string();
}

std::string peerEstimate(const RunJob& job) {
  return (fs::path(job.result_dir) / "stamped_traj_estimate.txt").string();
}

bool finishPeerRun(const RunJob& job) {
  std::error_code ec;
  if (fs::is_regular_file(peerPartialEstimate(job), ec) &&
      fs::file_size(peerPartialEstimate(job), ec) > 0) {
    fs::create_directories(job.result_dir, ec);
    fs::rename(peerPartialEstimate(job), peerEstimate(job), ec);
    if (!ec) return true;
  }
  std::ofstream(job.log, std::ios::app) << "error: " << job.peer_command
                                        << " exited 0 but wrote no estimate to "
                                        << peerPartialEstimate(job) << "\n";
  return false;
}

}  // namespace hdvio::bench
