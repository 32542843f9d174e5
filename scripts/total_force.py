#!/usr/bin/python3
"""All non-thrust force an hdvio run estimates: its external force plus the learned residual.

hdvio_run writes only the external force f_ext (stamped_force_estimate.csv, IMU frame). With a
residual-force model the dynamics see f_res + f_ext, so the estimate to compare with the
simulator's drag + external force ("total" in hdvio_eval) is their sum. The residual comes
from `hdvio_force_eval --weights <tcn> --out_csv <csv>` on the same sequence (100 Hz, body =
IMU frame, columns t [s], measured xyz, thrust xyz, thrust+tcn xyz); it is interpolated at the
estimate's stamps. Output: a vector CSV for `hdvio_eval --est name=<dir>:force=<out>`.

  total_force.py --force <run>/stamped_force_estimate.csv --residual <force_eval.csv> --out <csv>
"""
import argparse
import os
import sys

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--force", required=True, help="stamped_force_estimate.csv of an hdvio run")
    ap.add_argument("--residual", required=True, help="hdvio_force_eval --out_csv file")
    ap.add_argument("--out", required=True, help="output CSV (#timestamp [ns],x,y,z)")
    a = ap.parse_args()
    try:
        ext = np.loadtxt(a.force, delimiter=",", comments="#", ndmin=2)
        res = np.loadtxt(a.residual, delimiter=",", comments="#", ndmin=2)
    except (OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if ext.shape[1] != 4 or res.shape[1] != 10 or len(res) < 2:
        print(f"error: {a.force} needs 4 columns and {a.residual} 10", file=sys.stderr)
        return 2
    t_ns = ext[:, 0].astype(np.int64)
    t_res = res[:, 0]
    residual = res[:, 7:10] - res[:, 4:7]  # (thrust + tcn) - thrust
    t = t_ns * 1e-9
    inside = (t >= t_res[0]) & (t <= t_res[-1])
    total = ext[:, 1:4].copy()
    for i in range(3):
        total[inside, i] += np.interp(t[inside], t_res, residual[:, i])
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        f.write("#timestamp [ns],f_x [m s^-2],f_y [m s^-2],f_z [m s^-2]\n")
        for k in np.nonzero(inside)[0]:
            f.write(f"{t_ns[k]},{total[k, 0]:.9g},{total[k, 1]:.9g},{total[k, 2]:.9g}\n")
    os.replace(tmp, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
