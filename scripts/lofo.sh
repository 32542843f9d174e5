#!/usr/bin/env bash
# Leave-one-flight-out cross-validation of one residual-force experiment.
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
# FOLDS="2 3" reruns only those folds (e.g. after an interrupted run); the summary covers all
# folds whose evaluation exists.
for i in ${FOLDS:-${!flights[@]}}; do
  test=${flights[$i]}
  /usr/bin/time -f "fold $i: %e s wall, %U s user CPU" -a -o "$out/times.txt" \
    "$bin/hdvio_train" --config "$exp" --hold_out "$i" --data_root "$root" \
      --effective_config "$out/fold_$i.yaml" --out "$out/fold_$i.tcn" > "$out/fold_${i}_train.log"
  ct=$(awk '$1 == "thrust_coefficient:" {print $2}' "$out/fold_$i.yaml")
  mass=$(awk '$1 == "mass:" {print $2}' "$out/fold_$i.yaml")
  scale=1
  if grep -q '^  variance_head: true' "$out/fold_$i.yaml"; then
    # Recalibrate the variance head on the fold's training flights (68.3 % quantile of
    # |error| / sigma), then check the coverage on the held-out flight with that factor.
    trained=$("$bin/hdvio_train" --config "$out/fold_$i.yaml" --list_flights | paste -sd,)
    "$bin/hdvio_force_eval" --data_root "$root" --data "$trained" --thrust_coefficient "$ct" --mass "$mass" \
      --weights "$out/fold_$i.tcn" > "$out/fold_${i}_eval_train.txt"
    scale=$(grep '^variance head' "$out/fold_${i}_eval_train.txt" | tail -1 | sed 's/.*68.3 %: //')
  fi
  "$bin/hdvio_force_eval" --data_root "$root" --data "$test" --thrust_coefficient "$ct" --mass "$mass" \
    --weights "$out/fold_$i.tcn" --sigma_scale "$scale" > "$out/fold_${i}_eval.txt"
done
summary=$out/summary.md
{
  echo "# $exp: leave-one-flight-out, force RMSE [N] on the held-out flight"
  echo
  echo "| held-out flight | model | F | F_xy | F_z |"
  echo "|---|---|---|---|---|"
} > "$summary"
rm -f "$out/coverage.txt"
for i in "${!flights[@]}"; do
  eval_file=$out/fold_${i}_eval.txt
  [[ -f $eval_file ]] || continue
  name=$(basename "${flights[$i]}")
  # The "all flights" table of the evaluation = the held-out flight.
  awk -v f="$name" '/^all flights/ {on = 1; next}
       on && /^\| / && !/^\| model/ {split($0, c, "|"); gsub(/^ +| +$/, "", c[2]);
         printf "| %s | %s |%s|%s|%s|\n", f, c[2], c[3], c[4], c[5]}' "$eval_file" >> "$summary"
  grep '^variance head' "$eval_file" | tail -1 | sed "s|^|$name: |" >> "$out/coverage.txt" || true
done
cat "$summary"
[[ -f $out/coverage.txt ]] && cat "$out/coverage.txt"
cat "$out/times.txt"
