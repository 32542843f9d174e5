#!/usr/bin/env python3
"""Diagnostics for hdvio on simulated flights: what a velocity-aware residual model would give.

Fits a per-axis body-frame drag model to the true drag of calm training flights (least squares on
the ground-truth body velocity; `linear`: f = -d v_B, `quadratic`: f = -d v_B - c |v| v_B) and
writes copies of other flights whose force_groundtruth0 drag column is replaced by the model's
prediction at the true ground velocity. Running hdvio with `residual_force: {type: ground_truth}`
on such a copy gives the estimator "this drag model at the true velocity": in calm air the
quadratic model is exact; in wind it misses the airspeed, and the rest is left to the external
force (docs/hdvio_story.md, "A perfect residual model").

  drag_model_flights.py --mode quadratic --train <asl> [<asl> ...] --flights <asl> ... --out <dir>
"""
import argparse
import os
import shutil

import numpy as np

from dynamics_noise_calibration import quat_to_rot, read_csv


def load(folder):
    gt = read_csv(f"{folder}/mav0/state_groundtruth_estimate0/data.csv", min_cols=11)
    fg = read_csv(f"{folder}/mav0/force_groundtruth0/data.csv", min_cols=7)
    idx = np.clip(np.searchsorted(gt[:, 0], fg[:, 0]), 0, len(gt) - 1)
    R = quat_to_rot(gt[idx, 4:8])
    v_body = np.einsum("nji,nj->ni", R, gt[idx, 8:11])
    return fg, v_body


def design(v_body, axis, quadratic):
    cols = [v_body[:, axis]]
    if quadratic:
        cols.append(np.linalg.norm(v_body, axis=1) * v_body[:, axis])
    return np.stack(cols, 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mode", choices=["linear", "quadratic"], required=True)
    ap.add_argument("--train", nargs="+", required=True)
    ap.add_argument("--flights", nargs="+", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    quadratic = a.mode == "quadratic"
    data = [load(f) for f in a.train]
    coef = []
    for axis in range(3):
        X = np.concatenate([design(v, axis, quadratic) for _, v in data])
        y = np.concatenate([fg[:, 4 + axis] for fg, _ in data])
        coef.append(np.linalg.lstsq(X, y, rcond=None)[0])
    print(f"{a.mode} drag per body axis (coefficients of v_B[, |v| v_B]):", [c.round(4).tolist() for c in coef])
    for src in a.flights:
        fg, v = load(src)
        pred = np.stack([design(v, axis, quadratic) @ coef[axis] for axis in range(3)], 1)
        err = np.sqrt(((fg[:, 4:7] - pred) ** 2).mean(0))
        print(f"{os.path.basename(src)}: model error RMS x/y/z {err.round(3).tolist()} m/s^2")
        dst = os.path.join(a.out, os.path.basename(os.path.normpath(src)))
        if os.path.exists(dst):
            shutil.rmtree(dst)
        shutil.copytree(src, dst, symlinks=True)
        header = open(f"{src}/mav0/force_groundtruth0/data.csv").readline()
        with open(f"{dst}/mav0/force_groundtruth0/data.csv", "w") as f:
            f.write(header)
            for row, p in zip(fg, pred):
                f.write("%d,%s\n" % (int(row[0]), ",".join("%.10g" % x for x in list(row[1:4]) + list(p))))


if __name__ == "__main__":
    main()
