#!/usr/bin/env python3
"""Chooses the epoch count of the IMO displacement network from its cross-validation folds.

Reads <fold dir>/history.csv of each fold (hdvio_train_displacement --fold k --checkpoint_dir
<fold dir> --save_every s), averages the held-out MSE over the folds at every epoch all
folds reached (and that has an epoch_<e>.tcn when --save_every was used), and prints the epoch
with the smallest mean, the per-axis RMSE pooled over the folds' held-out data at that epoch
(the output_sigma of the final network) and the final training's flags.
    scripts/imo_cv_select.py --save_every 5 <fold0 dir> <fold1 dir> <fold2 dir>
Standard library only. Bad input: one line "error: <file>:<line>: <problem>", exit 2.
"""
import argparse
import csv
import math
import os
import sys


def read_history(path):
    rows = {}
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        for line, r in enumerate(reader, start=2):
            try:
                e = int(r["epoch"])
                mse = [float(r["validation_mse_" + a]) for a in "xyz"]
            except (KeyError, ValueError, TypeError):
                raise ValueError("%s:%d: not an epoch row of a fold history" % (path, line))
            if not all(math.isfinite(m) and m >= 0 for m in mse):
                raise ValueError("%s:%d: validation MSE is not a finite non-negative number" % (path, line))
            rows[e] = mse
    if not rows:
        raise ValueError("%s:0: no epochs" % path)
    return rows


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folds", nargs="+", help="fold checkpoint folders (history.csv inside)")
    ap.add_argument("--save_every", type=int, default=0,
                    help="> 0: only epochs with a checkpoint (multiples of it, epoch_<e>.tcn present)")
    args = ap.parse_args(argv)
    try:
        if len(args.folds) < 2:
            raise ValueError(":0: at least two folds are needed")
        histories = []
        for d in args.folds:
            p = os.path.join(d, "history.csv")
            if not os.path.isfile(p):
                raise ValueError("%s:0: missing (run the fold first)" % p)
            histories.append(read_history(p))
        common = set(histories[0])
        for h in histories[1:]:
            common &= set(h)
        common.discard(0)
        if args.save_every > 0:
            common = {e for e in common if e % args.save_every == 0 and
                      all(os.path.isfile(os.path.join(d, "epoch_%d.tcn" % e)) for d in args.folds)}
        if not common:
            raise ValueError("%s:0: no trained epoch common to all folds" % args.folds[0])
    except (OSError, ValueError) as e:
        print("error: %s" % e, file=sys.stderr)
        return 2
    mean = {e: sum(sum(h[e]) for h in histories) / len(histories) for e in common}
    best = min(sorted(common), key=lambda e: mean[e])
    sigma = [math.sqrt(sum(h[best][a] for h in histories) / len(histories)) for a in range(3)]
    print("epochs common to all folds: %d..%d (%d)" % (min(common), max(common), len(common)))
    for d, h in zip(args.folds, histories):
        print("%s: held-out MSE at epoch %d: %.6f m^2 (last epoch %d)" % (d, best, sum(h[best]), max(h)))
    print("chosen epoch %d: mean held-out MSE %.6f m^2" % (best, mean[best]))
    print("output_sigma (pooled held-out RMSE per axis) %.6f %.6f %.6f m" % tuple(sigma))
    print("final: --epochs %d --output_sigma %.6f,%.6f,%.6f" % ((best,) + tuple(sigma)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
