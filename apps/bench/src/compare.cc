#include "hdvio/bench/compare.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "hdvio/core/error.h"

namespace hdvio::bench {
namespace {
using Json = nlohmann::json;

std::string percent(double before, double after) {
  if (!(before > 0.0)) return "n/a";
  std::ostringstream s;
  s << std::showpos << std::fixed << std::setprecision(1) << 100.0 * (after / before - 1.0) << " %";
  return s.str();
}

std::string number(double x) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(4) << x;
  return s.str();
}
}  // namespace

std::vector<RunValue> readRunValues(const std::string& bench_dir, const std::string& metric) {
  const std::string path = (std::filesystem::path(bench_dir) / "results.json").string();
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open (not an hdvio_bench output folder?)");
  Json json;
  try {
    json = Json::parse(in);
  } catch (const Json::parse_error& e) {
    throw InputError(path, 0, std::string("malformed JSON: ") + e.what());
  }
  if (!json.contains("runs") || !json["runs"].is_array())
    throw InputError(path, 0, "no 'runs' array");
  std::vector<RunValue> values;
  bool metric_known = false;
  for (const Json& run : json["runs"]) {
    if (!run.is_object() || !run.contains("sequence") || !run.contains("experiment") ||
        !run.contains("status"))
      throw InputError(path, 0, "a run without sequence, experiment or status");
    if (run.contains(metric)) {
      const Json& v = run[metric];
      if (!v.is_null() && !v.is_number())
        throw InputError(path, 0, "metric '" + metric + "' is not a number");
      metric_known = true;
    }
    if (run["status"] != "ok" || !run.contains(metric) || !run[metric].is_number()) continue;
    RunValue r;
    r.sequence = run["sequence"].get<std::string>();
    r.experiment = run["experiment"].get<std::string>();
    r.seed = run.contains("seed") && run["seed"].is_number_integer() ? run["seed"].get<int>() : 0;
    r.value = run[metric].get<double>();
    values.push_back(r);
  }
  if (!metric_known && !json["runs"].empty())
    throw InputError(path, 0, "no metric '" + metric + "' in its runs");
  return values;
}

Comparison compareRuns(const std::vector<RunValue>& before, const std::vector<RunValue>& after) {
  using Run = std::tuple<std::string, std::string, int>;  // experiment, sequence, seed
  std::map<Run, double> old_values;
  for (const RunValue& r : before) old_values[{r.experiment, r.sequence, r.seed}] = r.value;
  std::vector<std::string> experiments, sequences;
  auto remember = [](std::vector<std::string>* order, const std::string& name) {
    if (std::find(order->begin(), order->end(), name) == order->end()) order->push_back(name);
  };
  std::map<std::pair<std::string, std::string>, ComparedCell> cells;
  for (const RunValue& r : after) {
    const auto old = old_values.find({r.experiment, r.sequence, r.seed});
    if (old == old_values.end()) continue;
    remember(&experiments, r.experiment);
    remember(&sequences, r.sequence);
    ComparedCell& c = cells[{r.experiment, r.sequence}];
    c.experiment = r.experiment;
    c.sequence = r.sequence;
    ++c.seeds;
    c.before += old->second;
    c.after += r.value;
    c.worse_seeds += r.value > old->second ? 1 : 0;
  }
  Comparison out;
  for (const std::string& e : experiments) {
    ComparedExperiment sum;
    sum.experiment = e;
    for (const std::string& s : sequences) {
      const auto it = cells.find({e, s});
      if (it == cells.end()) continue;
      ComparedCell c = it->second;
      c.before /= c.seeds;
      c.after /= c.seeds;
      sum.before_sum += c.before;
      sum.after_sum += c.after;
      ++sum.cells;
      sum.better_cells += c.after < c.before ? 1 : 0;
      out.cells.push_back(c);
    }
    out.experiments.push_back(sum);
  }
  return out;
}

std::string comparisonMarkdown(const Comparison& comparison, const std::string& metric,
                               const std::string& before_dir, const std::string& after_dir) {
  std::ostringstream md;
  md << "`" << metric << "`, seed means of the runs both have: before " << before_dir
     << ", after " << after_dir << "\n\n";
  md << "| experiment | sequence | seeds | before | after | change | seeds worse |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const ComparedCell& c : comparison.cells)
    md << "| " << c.experiment << " | " << c.sequence << " | " << c.seeds << " | "
       << number(c.before) << " | " << number(c.after) << " | " << percent(c.before, c.after)
       << " | " << c.worse_seeds << " of " << c.seeds << " |\n";
  md << "\n| experiment | sum before | sum after | change | sequences better |\n"
     << "|---|---|---|---|---|\n";
  for (const ComparedExperiment& e : comparison.experiments)
    md << "| " << e.experiment << " | " << number(e.before_sum) << " | " << number(e.after_sum)
       << " | " << percent(e.before_sum, e.after_sum) << " | " << e.better_cells << " of "
       << e.cells << " |\n";
  if (comparison.cells.empty()) md << "\n(no run is in both)\n";
  return md.str();
}

}  // namespace hdvio::bench
