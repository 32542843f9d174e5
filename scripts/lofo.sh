#!/usr/bin/env bash
# Leave-one-flight-out cross-validation of one residual-force experiment (issue 19).
#   scripts/lofo.sh <experiment.yaml> <out_dir> [data_root]
# The experiment is an hdvio_train config whose data.train lists all flights. Fold i trains on
# every flight but the i-th (hdvio_train --hold_out i; with data.refit_thrust_coefficient the
# thrust coefficient is refit on the fold's training flights) and hdvio_force_eval scores the
# i-th flight, which that fold never read. Writes per fold: the effective config
# (fold_<i>.yaml), training log, weights and evaluation; summary.md collects the tables.
# Run from the repository root with a HDVIO_WITH_TORCH=ON build in $BUILD (default build).
set -euo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 <experiment.yaml> <out_dir> [data_root]" >&2; exit 2; }
exp=$1 out=$2 root=${3:-../shared/data}
bin=${BUILD:-build}/apps/train
export OMP_NUM_THREADS=1
mkdir -p "$out"
cp "$exp" "$out/experiment.yaml"
exp=$out/experiment.yaml  # the folds read the copy: editing the original mid-run changes nothing
mapfile -t flights < <("$bin/hdvio_train" --config "$exp" --list_flights)
summary=$out/summary.md
{
  echo "# $exp: leave-one-flight-out, force RMSE [N] on the held-out flight"
  echo
  echo "| held-out flight | model | F | F_xy | F_z |"
  echo "|---|---|---|---|---|"
} > "$summary"
for i in "${!flights[@]}"; do
  test=${flights[$i]}
  /usr/bin/time -f "fold $i: %e s wall, %U s user CPU" -a -o "$out/times.txt" \
    "$bin/hdvio_train" --config "$exp" --hold_out "$i" --data_root "$root" \
      --effective_config "$out/fold_$i.yaml" --out "$out/fold_$i.tcn" > "$out/fold_${i}_train.log"
  ct=$(awk '$1 == "thrust_coefficient:" {print $2}' "$out/fold_$i.yaml")
  mass=$(awk '$1 == "mass:" {print $2}' "$out/fold_$i.yaml")
  "$bin/hdvio_force_eval" --data_root "$root" --data "$test" --thrust_coefficient "$ct" --mass "$mass" \
    --weights "$out/fold_$i.tcn" > "$out/fold_${i}_eval.txt"
  # The "all flights" table of the evaluation = the held-out flight.
  awk -v f="$(basename "$test")" '/^all flights/ {on = 1; next}
       on && /^\| / && !/^\| model/ {split($0, c, "|"); gsub(/^ +| +$/, "", c[2]);
         printf "| %s | %s |%s|%s|%s|\n", f, c[2], c[3], c[4], c[5]}' "$out/fold_${i}_eval.txt" >> "$summary"
  grep '^variance head' "$out/fold_${i}_eval.txt" | tail -1 | sed "s|^|<!-- $(basename "$test") -->  |" >> "$out/coverage.txt" || true
done
cat "$summary"
[[ -f $out/coverage.txt ]] && cat "$out/coverage.txt"
cat "$out/times.txt"
