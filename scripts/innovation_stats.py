#!/usr/bin/env python3
"""Normalized innovation squared of an inertial filter run (hdvio_run's innovations.csv).

    scripts/innovation_stats.py <run dir or innovations.csv> [...]
Prints per run and pooled: updates, mean NIS (3 on average for a consistent 3-dof
displacement update), mean NIS / 3 and per axis the mean of (r / sigma)^2 with sigma the
square root of S's diagonal (1 when consistent), and the per-axis factor sqrt(mean (r/sigma)^2)
that scripts/imo_cv.sh multiplies the measurement sigma with. Standard library only. Bad input: one line
"error: <file>:<line>: <problem>", exit 2.
"""
import math
import os
import sys


def read(path):
    if os.path.isdir(path):
        path = os.path.join(path, "innovations.csv")
    rows = []
    with open(path) as f:
        for line, text in enumerate(f, start=1):
            if text.startswith("#") or not text.strip():
                continue
            v = text.strip().split(",")
            try:
                r = [float(x) for x in v[1:4]]
                s = [float(x) for x in v[4:7]]
                nis = float(v[7])
            except (IndexError, ValueError):
                raise ValueError("%s:%d: not an innovations.csv row" % (path, line))
            if len(v) != 9 or not all(math.isfinite(x) for x in r + s + [nis]) or min(s) <= 0:
                raise ValueError("%s:%d: not an innovations.csv row" % (path, line))
            rows.append((r, s, nis))
    if not rows:
        raise ValueError("%s:0: no updates" % path)
    return rows


def summary(rows):
    n = len(rows)
    nis = sum(x[2] for x in rows) / n
    axis = [sum((x[0][a] / x[1][a]) ** 2 for x in rows) / n for a in range(3)]
    return "%d updates, mean NIS %.3f (%.3f per dof), per axis (r/sigma)^2 %.3f %.3f %.3f" % (
        n, nis, nis / 3, axis[0], axis[1], axis[2])


def main(argv):
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        runs = [(p, read(p)) for p in argv]
    except (OSError, ValueError) as e:
        print("error: %s" % e, file=sys.stderr)
        return 2
    for p, rows in runs:
        print("%s: %s" % (p, summary(rows)))
    pooled = [r for _, rows in runs for r in rows]
    if len(runs) > 1:
        print("pooled: %s" % summary(pooled))
    # The per-axis factor that would bring the pooled (r / sigma)^2 to 1 if S were all R.
    scale = [math.sqrt(sum((x[0][a] / x[1][a]) ** 2 for x in pooled) / len(pooled)) for a in range(3)]
    print("sigma scale to 1 per axis: %.6f %.6f %.6f" % tuple(scale))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
