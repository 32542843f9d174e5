#!/usr/bin/python3
"""Figures for an hdvio_bench result folder (run by hdvio_bench, or by hand:
/usr/bin/python3 plot_bench.py --dir <out>). Reads results.json and writes:
  ate_bars.png       ATE_T and ATE_R rmse per sequence, one bar per experiment (mean over seeds)
  runtime_bars.png   speed-up over real time per sequence and experiment
Trajectory overlays per sequence are in evaluation/<sequence>/ (plot_evaluation.py).
"""
import argparse
import json
import math
import os

import matplotlib

matplotlib.use("Agg")  # no display on servers
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def cell_means(runs, key):
    """{(sequence, experiment): mean of key over completed runs}"""
    values = {}
    for r in runs:
        v = r.get(key)
        if r["status"] == "ok" and v is not None and math.isfinite(v):
            values.setdefault((r["sequence"], r["experiment"]), []).append(v)
    return {k: float(np.mean(v)) for k, v in values.items()}


def grouped_bars(ax, sequences, experiments, means, ylabel):
    width = 0.8 / max(1, len(experiments))
    x = np.arange(len(sequences))
    for i, e in enumerate(experiments):
        heights = [means.get((s, e), np.nan) for s in sequences]
        ax.bar(x + (i - (len(experiments) - 1) / 2) * width, heights, width, label=e)
    ax.set_xticks(x)
    ax.set_xticklabels(sequences, rotation=20, ha="right")
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dir", required=True)
    args = parser.parse_args()
    with open(os.path.join(args.dir, "results.json")) as f:
        results = json.load(f)
    runs = results["runs"]
    sequences, experiments = [], []
    for r in runs:
        if r["sequence"] not in sequences:
            sequences.append(r["sequence"])
        if r["experiment"] not in experiments:
            experiments.append(r["experiment"])

    fig, axes = plt.subplots(2, 1, figsize=(max(6, 1.5 * len(sequences) + 3), 7), sharex=True)
    grouped_bars(axes[0], sequences, experiments, cell_means(runs, "ate_t_m"), "ATE_T rmse [m]")
    grouped_bars(axes[1], sequences, experiments, cell_means(runs, "ate_r_deg"), "ATE_R rmse [deg]")
    axes[0].legend()
    axes[0].set_title("alignment: " + results["alignment"])
    fig.tight_layout()
    fig.savefig(os.path.join(args.dir, "ate_bars.png"), dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(max(6, 1.5 * len(sequences) + 3), 4))
    grouped_bars(ax, sequences, experiments, cell_means(runs, "realtime_factor"),
                 "sequence duration / stage time (x real time)")
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.dir, "runtime_bars.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
