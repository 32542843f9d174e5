#!/usr/bin/python3
"""Figures for an hdvio_eval result folder (run by `hdvio_eval --plots`, or by hand:
/usr/bin/python3 plot_evaluation.py --dir <out>). Reads metrics.json and plot_data/*.csv and
writes PNGs next to them:
  trajectory_top.png, trajectory_side.png   ground truth vs aligned estimates (x-y, x-z)
  translation_error.png                     absolute translation error over time
  relative_error_boxplot.png                rpg relative translation error per distance
  force_<name>.png                          force components vs ground truth (if any)
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display on servers
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

COLORS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]


def load_csv(path):
    data = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    return data


def color(i):
    return COLORS[i % len(COLORS)]


def trajectory_views(out, gt, estimates, subtitle):
    for name, (a, b), labels in (("top", (1, 2), ("x [m]", "y [m]")),
                                 ("side", (1, 3), ("x [m]", "z [m]"))):
        fig, ax = plt.subplots(figsize=(7, 6))
        ax.plot(gt[:, a], gt[:, b], color="k", lw=1.5, label="ground truth")
        for i, (est, data) in enumerate(estimates):
            ax.plot(data[:, a], data[:, b], color=color(i), lw=1.0, label=est["name"])
        ax.set_xlabel(labels[0])
        ax.set_ylabel(labels[1])
        if name == "top":
            ax.set_aspect("equal", adjustable="datalim")  # side view: z range is small, keep it readable
        ax.grid(True, alpha=0.3)
        ax.legend()
        ax.set_title("%s view (%s)" % (name, subtitle))
        fig.tight_layout()
        fig.savefig(os.path.join(out, "trajectory_%s.png" % name), dpi=120)
        plt.close(fig)


def translation_error(out, estimates, subtitle, by_index):
    fig, ax = plt.subplots(figsize=(8, 4))
    for i, (est, data) in enumerate(estimates):
        rmse = est["ate_translation_m"]["rmse"]
        ax.plot(data[:, 0], data[:, 7], color=color(i), lw=1.0,
                label="%s (rmse %.3f m)" % (est["name"], rmse))
    ax.set_xlabel("pose index" if by_index else "time [s]")
    ax.set_ylabel("translation error [m]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    ax.set_title("absolute translation error (%s)" % subtitle)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "translation_error.png"), dpi=120)
    plt.close(fig)


def relative_boxplot(out, metrics, plot_dir):
    distances = sorted({r["distance_m"] for e in metrics["estimates"] for r in e["relative_errors"]})
    if not distances:
        return
    n = len(metrics["estimates"])
    width = 0.8 / max(n, 1)
    fig, ax = plt.subplots(figsize=(min(12, max(6, 1.0 * len(distances) * max(n, 1))), 4.5))
    for i, est in enumerate(metrics["estimates"]):
        data = load_csv(os.path.join(plot_dir, "est%d_relative.csv" % est["index"]))
        groups = [data[np.isclose(data[:, 0], d), 1] if data.size else np.array([]) for d in distances]
        positions = [k + (i - (n - 1) / 2.0) * width for k in range(len(distances))]
        keep = [k for k, g in enumerate(groups) if g.size > 0]
        if not keep:
            continue
        bp = ax.boxplot([groups[k] for k in keep], positions=[positions[k] for k in keep],
                        widths=width * 0.9, patch_artist=True, showfliers=False,
                        medianprops={"color": "k"})
        for box in bp["boxes"]:
            box.set_facecolor(color(i))
            box.set_alpha(0.6)
        ax.plot([], [], color=color(i), lw=6, alpha=0.6, label=est["name"])
    ax.set_xticks(range(len(distances)))
    ax.set_xticklabels(["%.2f" % d for d in distances])
    ax.set_xlabel("distance traveled [m]")
    ax.set_ylabel("translation error [m]")
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend()
    ax.set_title("relative translation error (rpg sub-trajectories)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "relative_error_boxplot.png"), dpi=120)
    plt.close(fig)


def force_plot(out, est, data):
    fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
    for k, axis in enumerate("xyz"):
        ax = axes[k]
        ax.plot(data[:, 0], data[:, 1 + k], color="tab:red", lw=1.0, alpha=0.7,
                label="estimate (external)")
        if data.shape[1] >= 13 and np.abs(data[:, 10:13] - data[:, 1:4]).max() > 0:
            ax.plot(data[:, 0], data[:, 10 + k], color="tab:green", lw=1.0, alpha=0.8,
                    label="estimate, total (residual + external)")
        ax.plot(data[:, 0], data[:, 4 + k], color="k", lw=1.2, label="external gt")
        ax.plot(data[:, 0], data[:, 7 + k], color="tab:blue", lw=1.2, ls="--",
                label="total gt (ext + drag)")
        ax.set_ylabel("f_%s [m/s^2]" % axis)
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    ext = est["force_external_m_s2"]["total"]["rmse"]
    tot = est["force_total_m_s2"]["total"]["rmse"]
    axes[0].set_title("%s: force (IMU frame), rmse external %.3f, total %.3f m/s^2" % (est["name"], ext, tot))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "force_%s.png" % est["name"]), dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dir", required=True, help="hdvio_eval --out folder")
    args = parser.parse_args()
    metrics_path = os.path.join(args.dir, "metrics.json")
    plot_dir = os.path.join(args.dir, "plot_data")
    if not os.path.exists(metrics_path) or not os.path.isdir(plot_dir):
        print("error: %s is not an hdvio_eval result folder" % args.dir, file=sys.stderr)
        return 2
    with open(metrics_path) as f:
        metrics = json.load(f)
    subtitle = "align: %s" % metrics["options"]["alignment"]
    gt = load_csv(os.path.join(plot_dir, "groundtruth.csv"))
    estimates = [(e, load_csv(os.path.join(plot_dir, "est%d_aligned.csv" % e["index"])))
                 for e in metrics["estimates"]]
    trajectory_views(args.dir, gt, estimates, subtitle)
    translation_error(args.dir, estimates, subtitle, metrics["options"]["association"] == "index")
    relative_boxplot(args.dir, metrics, plot_dir)
    for est in metrics["estimates"]:
        path = os.path.join(plot_dir, "est%d_force.csv" % est["index"])
        if est["force_external_m_s2"] is not None and os.path.exists(path):
            force_plot(args.dir, est, load_csv(path))
    print("figures written to %s" % args.dir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
