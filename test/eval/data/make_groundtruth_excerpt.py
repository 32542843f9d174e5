# Keeps the header and the ground-truth lines evo's association uses for V102.txt, plus the line
# after each, so the ground truth stays the longer trajectory (evo matches short against long).
import sys
import numpy as np
from evo.tools import file_interface
from evo.core import sync
gt_path, est_path, out_path = sys.argv[1:4]
gt = file_interface.read_euroc_csv_trajectory(gt_path)
est = file_interface.read_tum_trajectory_file(est_path)
ids_est, ids_gt = sync.matching_time_indices(est.timestamps, gt.timestamps, 0.01)
keep = sorted(set(ids_gt) | {i + 1 for i in ids_gt if i + 1 < len(gt.timestamps)})
lines = open(gt_path).read().splitlines()
header = [l for l in lines if l.startswith("#")]
data = [l for l in lines if not l.startswith("#")]
assert len(data) == len(gt.timestamps)
with open(out_path, "w") as f:
    for l in header: f.write(l + "\n")
    for i in keep: f.write(data[i] + "\n")
print(len(ids_gt), "matches,", len(set(ids_gt)), "distinct gt rows,", len(keep), "rows kept")
