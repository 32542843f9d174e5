#!/usr/bin/env python3
"""Calibrates hdvio's dynamics noise model on simulated flights (never on benchmark flights).

The dynamics factor predicts the velocity change from thrust + learned residual force; what it
misses is e(t) = (drag + external)_true - f_res(t), which the backend models in the world frame as
  e_W(t) = f_ext(t) + w(t),   f_ext a random walk (force_random_walk, m/s^2/sqrt(s)),
                              w white noise (thrust_noise_density, m/s^2/sqrt(Hz)).
Averaged over intervals of length D (what one factor sees), consecutive differences have the
per-axis variance  V(D) = rw^2 D + 2 q^2 / D.  V is measured for several D and (rw^2, q^2) fitted
by non-negative least squares (weights 1/V, i.e. relative error).

Inputs per flight: the ASL folder from hdvio_sim (ground-truth pose and force) and the per-sample
output of `hdvio_force_eval --out_csv` (t, measured, thrust, thrust + TCN, body frame).
  dynamics_noise_calibration.py --flight <asl folder> <force_eval.csv> [--flight ...]
"""
import argparse
import os
import sys
import warnings

import numpy as np


def fail(path, problem):
    print(f"error: {path}: {problem}", file=sys.stderr)
    sys.exit(2)


def read_csv(path, min_cols=1):
    """Numeric CSV ('#' comments) as a 2-D array; exits 2 naming the file on bad input."""
    if not os.path.isfile(path):
        fail(path, "no such file")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # ragged rows / empty file -> error, not a warning
            d = np.genfromtxt(path, delimiter=",", comments="#", ndmin=2)
    except (ValueError, UserWarning) as e:
        fail(path, f"not a numeric CSV ({str(e).splitlines()[0]})")
    if d.shape[0] == 0 or d.shape[1] < min_cols:
        fail(path, f"expected at least {min_cols} columns and one row, found {d.shape[1]} x {d.shape[0]}")
    bad = np.argwhere(~np.isfinite(d))
    if len(bad):
        fail(path, f"row {bad[0][0] + 1} (data row), column {bad[0][1] + 1}: not a number")
    if np.any(np.diff(d[:, 0]) <= 0):
        fail(path, f"timestamps not strictly increasing at data row {int(np.argmax(np.diff(d[:, 0]) <= 0)) + 2}")
    return d


def quat_to_rot(q):  # q: N x 4 (w, x, y, z)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def world_error(folder, eval_csv):
    ev = read_csv(eval_csv, min_cols=10)
    t = ev[:, 0]
    f_res = ev[:, 7:10] - ev[:, 4:7]  # (thrust + TCN) - thrust
    fg = read_csv(f"{folder}/mav0/force_groundtruth0/data.csv", min_cols=7)
    tg = fg[:, 0] * 1e-9
    true_force = np.stack([np.interp(t, tg, fg[:, 1 + i] + fg[:, 4 + i]) for i in range(3)], -1)
    gt = read_csv(f"{folder}/mav0/state_groundtruth_estimate0/data.csv", min_cols=11)
    idx = np.clip(np.searchsorted(gt[:, 0] * 1e-9, t), 0, len(gt) - 1)
    R = quat_to_rot(gt[idx, 4:8])
    e_body = true_force - f_res
    return t, np.einsum("nij,nj->ni", R, e_body), e_body


def interval_difference_variance(t, e, D):
    dt = np.median(np.diff(t))
    n = max(1, int(round(D / dt)))
    m = len(e) // n
    means = e[: m * n].reshape(m, n, 3).mean(axis=1)
    return np.mean(np.diff(means, axis=0) ** 2), m - 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--flight", nargs=2, action="append", required=True, metavar=("ASL", "CSV"))
    ap.add_argument("--intervals", default="0.05,0.1,0.2,0.4,0.8")
    a = ap.parse_args()
    Ds = [float(x) for x in a.intervals.split(",")]
    rows = {D: [] for D in Ds}
    for folder, csv in a.flight:
        t, e_w, e_b = world_error(folder, csv)
        print(f"{folder}: {len(t)} samples, model error rms (body, per axis) "
              f"{np.sqrt(np.mean(e_b ** 2, axis=0)).round(3)}, |e| rms {np.sqrt(np.mean(np.sum(e_b ** 2, 1))):.3f} m/s^2")
        for D in Ds:
            rows[D].append(interval_difference_variance(t, e_w, D))
    V = np.array([sum(v * n for v, n in rows[D]) / sum(n for _, n in rows[D]) for D in Ds])
    A = np.stack([np.array(Ds), 2.0 / np.array(Ds)], -1) / V[:, None]
    b = np.ones_like(V)
    best = None
    for mask in ([1, 1], [1, 0], [0, 1]):  # non-negative least squares by enumeration
        cols = [i for i in range(2) if mask[i]]
        x = np.zeros(2)
        x[cols] = np.linalg.lstsq(A[:, cols], b, rcond=None)[0]
        if (x < 0).any():
            continue
        r = np.sum((A @ x - b) ** 2)
        if best is None or r < best[0]:
            best = (r, x)
    rw2, q2 = best[1]
    print("| interval D [s] | measured V(D) [(m/s^2)^2] | fitted |")
    print("|---|---|---|")
    for D, v in zip(Ds, V):
        print(f"| {D:.2f} | {v:.4f} | {rw2 * D + 2 * q2 / D:.4f} |")
    print(f"force_random_walk = {np.sqrt(rw2):.3f} m/s^2/sqrt(s), "
          f"white-noise density = {np.sqrt(q2):.4f} m/s^2/sqrt(Hz)")


if __name__ == "__main__":
    main()
