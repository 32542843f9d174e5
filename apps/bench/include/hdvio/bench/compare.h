#pragma once
// Two benchmark outputs of the same matrix compared run by run (`hdvio_bench --compare`): per
// experiment and sequence the seed mean of a metric before and after, how many seeds got worse,
// and per experiment the sum of the seed means. Only runs that have numbers in both count, and
// only seeds both have, so a cell compares like with like.
#include <string>
#include <vector>

namespace hdvio::bench {

struct RunValue {
  std::string sequence, experiment;
  int seed = 0;  // 0: a run without a seed
  double value = 0.0;
};

// The runs of <dir>/results.json with status ok and a number for metric (a numeric field of its
// runs, e.g. ate_t_m, ms_per_image_mean). InputError for a missing or malformed file or an
// unknown metric.
std::vector<RunValue> readRunValues(const std::string& bench_dir, const std::string& metric);

struct ComparedCell {
  std::string experiment, sequence;
  int seeds = 0;        // seeds in both
  double before = 0.0;  // seed means
  double after = 0.0;
  int worse_seeds = 0;  // seeds whose value grew
};

struct ComparedExperiment {
  std::string experiment;
  double before_sum = 0.0, after_sum = 0.0;  // sums of the cells' seed means
  int cells = 0, better_cells = 0;
};

struct Comparison {
  std::vector<ComparedCell> cells;              // experiments, then sequences, in 'after' order
  std::vector<ComparedExperiment> experiments;  // in 'after' order
};

Comparison compareRuns(const std::vector<RunValue>& before, const std::vector<RunValue>& after);

// Markdown tables of a comparison (lower is better for every metric the bench writes).
std::string comparisonMarkdown(const Comparison& comparison, const std::string& metric,
                               const std::string& before_dir, const std::string& after_dir);

}  // namespace hdvio::bench
