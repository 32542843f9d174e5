#!/usr/bin/env bash
# Sets up, builds and runs the main job on the embedded default: generates a synthetic
# quadrotor flight with drag and wind (hdvio_sim), runs the vio, vimo, vid and hdvio backends
# on its landmark tracks (hdvio_run), and prints the evaluation table with figures
# (hdvio_eval). Everything goes to results/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target hdvio_sim hdvio_run hdvio_eval hdvio_info
out=results/demo
rm -rf "$out" && mkdir -p "$out"
build/apps/sim/hdvio_sim --config config/sim/demo.yaml --out "$out/sequence"
build/apps/tools/hdvio_info "$out/sequence"
estimates=()
for method in vio vimo vid hdvio; do
  build/apps/run/hdvio_run --config "config/experiments/$method.yaml" \
    --dataset "$out/sequence" --out "$out/$method"
  estimates+=("$method=$out/$method")
done
build/apps/eval/hdvio_eval --gt "$out/sequence" --est "$(IFS=,; echo "${estimates[*]}")" \
  --out "$out/evaluation" --plots
echo "demo: results, table and figures in $out/"
