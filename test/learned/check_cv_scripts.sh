#!/bin/sh
# scripts/imo_cv_select.py and scripts/innovation_stats.py on small hand-made inputs with known
# answers: the epoch with the smallest mean fold MSE among the checkpointed epochs all folds
# reached, the pooled per-axis RMSE there, and the mean NIS / per-axis (r/sigma)^2 / scale of an
# innovations.csv; malformed input gives exit 2 and one "error: " line.
# Usage: check_cv_scripts.sh <python3> <source dir>
set -u
PY=$1; SRC=$2; T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "$1"; exit 1; }
mkdir -p "$T/f0" "$T/f1"
H="epoch,train_loss,validation_mse,validation_mse_x,validation_mse_y,validation_mse_z,seconds"
# Epoch 7 is the best of all but has no checkpoint; fold 1 stops at epoch 11.
printf '%s\n0,1,3,1,1,1,1\n5,1,0.005,0.002,0.002,0.001,1\n7,1,0.0001,0.00005,0.00004,0.00001,1\n10,1,0.0025,0.001,0.001,0.0005,1\n12,1,0.001,0.0004,0.0004,0.0002,1\n' "$H" > "$T/f0/history.csv"
printf '%s\n0,1,3,1,1,1,1\n5,1,0.005,0.003,0.001,0.001,1\n7,1,0.0001,0.00005,0.00004,0.00001,1\n10,1,0.005,0.002,0.002,0.001,1\n11,1,0.001,0.0004,0.0004,0.0002,1\n' "$H" > "$T/f1/history.csv"
for d in f0 f1; do for e in 5 10 12; do : > "$T/$d/epoch_$e.tcn"; done; done
out=$("$PY" "$SRC/scripts/imo_cv_select.py" --save_every 5 "$T/f0" "$T/f1") || fail "imo_cv_select failed"
echo "$out" | grep -qx "final: --epochs 10 --output_sigma 0.038730,0.038730,0.027386" || fail "wrong choice: $out"
rm "$T/f1/epoch_10.tcn"  # then epoch 10 has no checkpoint in every fold: epoch 5 (mean 0.005)
out=$("$PY" "$SRC/scripts/imo_cv_select.py" --save_every 5 "$T/f0" "$T/f1") || fail "imo_cv_select failed"
echo "$out" | grep -qx "final: --epochs 5 --output_sigma 0.050000,0.038730,0.031623" || fail "wrong choice: $out"
printf '%s\n5,1,0.005,nan,0.002,0.001,1\n' "$H" > "$T/f1/history.csv"
"$PY" "$SRC/scripts/imo_cv_select.py" "$T/f0" "$T/f1" 2>"$T/err" >/dev/null; rc=$?
[ $rc -eq 2 ] && grep -q "^error: $T/f1/history.csv:2: " "$T/err" && [ $(wc -l < "$T/err") -eq 1 ] \
  || fail "NaN history: exit $rc, $(cat "$T/err")"
printf '#timestamp [ns],r_x [m],r_y [m],r_z [m],sigma_x [m],sigma_y [m],sigma_z [m],nis,applied\n1,0.1,0,0,0.1,1,1,1,1\n2,0,0.2,0,1,0.1,1,4,1\n' > "$T/innovations.csv"
out=$("$PY" "$SRC/scripts/innovation_stats.py" "$T") || fail "innovation_stats failed"
echo "$out" | grep -q ": 2 updates, mean NIS 2.500 (0.833 per dof), per axis (r/sigma)^2 0.500 2.000 0.000$" || fail "wrong stats: $out"
echo "$out" | grep -qx "sigma scale to 1 per axis: 0.707107 1.414214 0.000000" || fail "wrong scale: $out"
printf '1,0.1,0,0,0,1,1,1,1\n' > "$T/innovations.csv"  # sigma 0
"$PY" "$SRC/scripts/innovation_stats.py" "$T" 2>"$T/err" >/dev/null; rc=$?
[ $rc -eq 2 ] && grep -q "^error: $T/innovations.csv:1: " "$T/err" || fail "bad row: exit $rc, $(cat "$T/err")"
echo ok
