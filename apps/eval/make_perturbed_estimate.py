#!/usr/bin/python3
"""Makes perturbed copies of a TUM-order ground truth (e.g. Blackbird's
stamped_groundtruth_imu.txt, `ts x y z qx qy qz qw vx vy vz`) to check hdvio_eval's numbers and
figures end to end. Not data: regenerate it, do not commit it.

For each of two estimates it writes <out>/<name>/stamped_traj_estimate.txt,
stamped_velocity_estimate.csv and stamped_force_estimate.csv, plus <out>/force_groundtruth.csv:
  - a constant yaw offset and translation (removed by posyaw alignment),
  - a seeded 3-D random-walk drift of the position (what ATE/RPE should see),
  - small orientation noise, velocity noise,
  - a synthetic force ground truth (linear drag -k R^T v plus two external "gusts") and
    estimates of it with a lag and noise.
Usage: make_perturbed_estimate.py --gt <file> --out <dir> [--seed 7]
"""
import argparse
import os

import numpy as np


def quat_mult(a, b):  # xyzw
    ax, ay, az, aw = a.T
    bx, by, bz, bw = b.T
    return np.stack([aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw,
                     aw * bw - ax * bx - ay * by - az * bz], axis=1)


def quat_to_rot(q):  # xyzw -> (N, 3, 3)
    x, y, z, w = q.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                     np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                     np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)


def small_rotation_quats(rng, n, sigma_rad):
    phi = rng.normal(0.0, sigma_rad, size=(n, 3))
    angle = np.linalg.norm(phi, axis=1, keepdims=True)
    axis = np.where(angle > 0, phi / np.maximum(angle, 1e-12), 0.0)
    return np.hstack([axis * np.sin(angle / 2), np.cos(angle / 2)])


def write_csv(path, header, t_ns, values):
    with open(path, "w") as f:
        f.write(header + "\n")
        for t, v in zip(t_ns, values):
            f.write("%d,%s\n" % (t, ",".join("%.9f" % x for x in v)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gt", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)

    # Stamps as text so the ns values stay exact.
    rows = [l.split() for l in open(args.gt) if l.strip() and not l.startswith("#")]
    stamps = [r[0] for r in rows]
    data = np.array([[float(x) for x in r[1:]] for r in rows])
    p, q = data[:, 0:3], data[:, 3:7]
    v = data[:, 7:10] if data.shape[1] >= 10 else np.gradient(p, axis=0) * 100.0
    t_ns = np.array([int(s.split(".")[0]) * 10**9 + int((s.split(".")[1] + "000000000")[:9]) if "." in s
                     else int(s) * 10**9 for s in stamps], dtype=np.int64)
    n = len(p)
    os.makedirs(args.out, exist_ok=True)

    # Synthetic force ground truth in the IMU frame (mass-normalized).
    R = quat_to_rot(q)
    drag = -0.35 * np.einsum("nji,nj->ni", R, v)  # -k R^T v
    ts = (t_ns - t_ns[0]) * 1e-9
    ext = np.zeros((n, 3))
    for center, amp in ((8.0, np.array([2.0, -1.0, 0.5])), (20.0, np.array([-1.5, 1.5, -1.0]))):
        ext += np.exp(-0.5 * ((ts - center) / 1.5) ** 2)[:, None] * amp
    write_csv(os.path.join(args.out, "force_groundtruth.csv"),
              "#timestamp [ns],f_ext_x [m s^-2],f_ext_y,f_ext_z,f_drag_x,f_drag_y,f_drag_z",
              t_ns, np.hstack([ext, drag]))

    for name, drift_sigma, yaw_deg, force_noise in (("drift_small", 0.002, 30.0, 0.1),
                                                     ("drift_large", 0.008, -75.0, 0.3)):
        yaw = np.deg2rad(yaw_deg)
        q_yaw = np.array([[0.0, 0.0, np.sin(yaw / 2), np.cos(yaw / 2)]])
        R_yaw = quat_to_rot(q_yaw)[0]
        drift = np.cumsum(rng.normal(0.0, drift_sigma, size=(n, 3)), axis=0)
        p_est = (R_yaw @ p.T).T + np.array([1.0, -2.0, 0.5]) + drift
        q_est = quat_mult(np.repeat(q_yaw, n, 0), quat_mult(q, small_rotation_quats(rng, n, 0.005)))
        v_est = (R_yaw @ v.T).T + rng.normal(0.0, 0.05, size=(n, 3))
        lag = 5  # samples
        f_est = np.vstack([np.repeat(ext[:1] + drag[:1], lag, 0), (ext + drag)[:-lag]])
        f_est = f_est + rng.normal(0.0, force_noise, size=(n, 3))
        d = os.path.join(args.out, name)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "stamped_traj_estimate.txt"), "w") as f:
            f.write("# timestamp[s] tx ty tz qx qy qz qw\n")
            for s, pp, qq in zip(stamps, p_est, q_est):
                f.write("%s %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % ((s,) + tuple(pp) + tuple(qq)))
        write_csv(os.path.join(d, "stamped_velocity_estimate.csv"), "#timestamp [ns],v_x,v_y,v_z", t_ns, v_est)
        write_csv(os.path.join(d, "stamped_force_estimate.csv"), "#timestamp [ns],f_x,f_y,f_z", t_ns, f_est)
        print("%s: yaw offset %.1f deg, final drift %.3f m" % (name, yaw_deg, np.linalg.norm(drift[-1])))


if __name__ == "__main__":
    main()
