#pragma once
// When the sequence has ground truth, hdvio_run evaluates its own result (the table and figures
// of hdvio_eval) into <out>/evaluation/. hdvio_bench reuses the ground-truth loading so that its
// numbers are the ones hdvio_eval prints for the same folders.
#include <optional>
#include <string>
#include <utility>

#include "hdvio/core/sequence.h"
#include "hdvio/eval/evaluation.h"

namespace hdvio::run {

struct RunEvaluationOptions {
  bool plots = true;  // figures need /usr/bin/python3 with matplotlib; skipped with a note if absent
  eval::AlignmentType alignment = eval::AlignmentType::kPosYaw;
  // When set (RunResults::input_span), the rpg sub-trajectory lengths are fractions of the
  // ground truth's length over this span: a run on part of a flight gets lengths of that part,
  // not of the whole flight.
  std::optional<std::pair<Timestamp, Timestamp>> ground_truth_span;
};

// Ground truth exactly as hdvio_eval reads it when dataset_path is an ASL folder (its
// state_groundtruth_estimate0 and force_groundtruth0); for other flights (Blackbird, DIDO,
// NeuroBEM) converted from the sequence, which is read from dataset_path when seq is null.
// Empty when the sequence has no ground truth. Throws InputError for unreadable input.
std::optional<eval::GroundTruth> loadRunGroundTruth(const std::string& dataset_path,
                                                    const Sequence* seq);

// The figures script of hdvio_eval (plot_evaluation.py): $HDVIO_EVAL_PLOT_SCRIPT, next to the
// running binary (installed), or in the source tree of the build tree the binary lives in.
// Empty if none is found.
std::string findEvalPlotScript();

// results_dir holds a complete hdvio_run result. Writes <results_dir>/evaluation/ (table.md,
// metrics.json, plot_data/, figures) and prints the table on stdout. Never throws: a sequence
// without ground truth, an evaluation error or missing python are reported on stderr and the
// function returns false (figures missing alone still returns true, with a note); the run's
// own results stay valid either way.
bool evaluateRun(const Sequence& seq, const std::string& dataset_path,
                 const std::string& results_dir, const RunEvaluationOptions& options);

}  // namespace hdvio::run
