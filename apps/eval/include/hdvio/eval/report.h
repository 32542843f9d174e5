#pragma once
// What an evaluation leaves behind: a Markdown table (also printed), metrics.json, and the
// CSVs plot_evaluation.py draws from. Files are written under a temporary name and renamed,
// so an interrupted run never leaves a half-written result that looks complete.
#include <string>
#include <vector>

#include "hdvio/eval/evaluation.h"

namespace hdvio::eval {

struct EvaluationReport {
  std::string ground_truth_source;
  EvaluationOptions options;
  std::vector<double> distances;
  std::vector<EstimateResult> results;
};

std::string formatTable(const EvaluationReport& report);
std::string formatJson(const EvaluationReport& report);

// Writes table.md, metrics.json and plot_data/*.csv into out_dir (created if needed).
void writeReport(const EvaluationReport& report, const GroundTruth& gt, const std::string& out_dir);

// Writes text to path via path + ".tmp" and a rename.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace hdvio::eval
