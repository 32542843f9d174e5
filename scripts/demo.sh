#!/usr/bin/env bash
# The product's story in one command (docs/hdvio_story.md):
#   1. set up (Debian packages incl. libtorch for the trainer) and build the tools;
#   2. simulate a calm-air training flight and a separate fast test flight (race through gates)
#      with rotor/fuselage drag, a breeze and gusts, rendered as 752x480 camera images (hdvio_sim);
#   3. train the residual-force TCN on the training flight only (hdvio_train, bounded: at most
#      40 epochs or 2 minutes on one thread) and check its force prediction on the test flight
#      (hdvio_force_eval);
#   4. run vio, vimo, vid and hdvio with the trained model on the test flight's camera images
#      (semi-direct frontend + sliding-window smoother, the project's own start: static, the
#      flight starts at rest; hdvio_run, in parallel), and OpenVINS beside them when its peer
#      build exists (../shared/peers/openvins, started from ground truth as that runner does);
#   5. print the evaluation table (ATE, RPE, velocity and force RMSE) and write figures
#      (hdvio_eval --plots).
# Everything goes to results/demo/.
# Usage: scripts/demo.sh [--skip-setup] [--build-dir DIR]
#   --build-dir DIR: use an existing build configured with -DHDVIO_WITH_TORCH=ON (skips setup,
#   configure and build), e.g. to re-run the story after changing a config.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
setup=1
build=build-demo   # its own build folder: the trainer needs libtorch, scripts/test.sh does not
prebuilt=0
while [ $# -gt 0 ]; do
  case "$1" in
    --skip-setup) setup=0 ;;
    --build-dir) [ $# -ge 2 ] || { echo "demo.sh: --build-dir needs a folder" >&2; exit 2; }
                 build=$2; prebuilt=1; setup=0; shift ;;
    *) echo "demo.sh: unknown argument '$1' (expected --skip-setup or --build-dir DIR)" >&2; exit 2 ;;
  esac
  shift
done
if [ "$setup" -eq 1 ]; then bash scripts/setup.sh --with-torch; fi
jobs=$(nproc 2>/dev/null || echo 2)
if [ "$prebuilt" -eq 0 ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DHDVIO_WITH_TORCH=ON
  cmake --build "$build" -j"$jobs" --target hdvio_sim hdvio_run hdvio_eval hdvio_info hdvio_train hdvio_force_eval
fi
bin=$build/apps
out=results/demo
rm -rf "$out" && mkdir -p "$out/model"
step() { echo; echo "== demo ($(($(date +%s) - start)) s): $*"; }

step "simulating the training flight and the test flight"
"$bin/sim/hdvio_sim" --config config/sim/demo_train.yaml --out "$out/train"
"$bin/sim/hdvio_sim" --config config/sim/demo.yaml --out "$out/sequence"
"$bin/tools/hdvio_info" "$out/sequence"

step "training the residual-force model (drag law + TCN on the rest) on the training flight"
"$bin/train/hdvio_train" --config config/learned/sim_demo_train.yaml --data_root "$out" \
  --out "$out/model/residual_force.tcn" | tee "$out/model/training.log"

step "force prediction on the test flight (never trained on): thrust alone vs thrust + model"
"$bin/train/hdvio_force_eval" --data_root "$out" --data sequence \
  --weights "$out/model/residual_force.tcn" | tee "$out/model/force_eval.md"

step "running vio, vimo, vid and hdvio (trained model) on the test flight's camera images"
methods=(vio vimo vid hdvio)
configs=(config/experiments/sim_images_vio.yaml config/experiments/sim_images_vimo.yaml
         config/experiments/sim_images_vid.yaml config/experiments/hdvio_learned_demo.yaml)
pids=()
for i in "${!methods[@]}"; do  # all at once: each is single-threaded, the OS shares the cores
  # --evaluate=false: the joint evaluation below compares all methods in one table
  "$bin/run/hdvio_run" --config "${configs[$i]}" --dataset "$out/sequence" --out "$out/${methods[$i]}" \
    --evaluate=false > "$out/${methods[$i]}.log" 2>&1 &
  pids+=($!)
done
for i in "${!methods[@]}"; do
  wait "${pids[$i]}" || { cat "$out/${methods[$i]}.log" >&2; echo "demo.sh: ${methods[$i]} failed" >&2; exit 1; }
done
for m in "${methods[@]}"; do
  echo "$m: $(grep -h 'frontend saw' "$out/$m.log" | sed 's/^hdvio_run: //')"
done

# The peer a user would pick instead: OpenVINS (mono), when built (its build needs a snapshot of
# rpng/open_vins, see ../shared/peers/openvins/README.md; ~15 min on 2 cores).
estimates="vio=$out/vio,vimo=$out/vimo,vid=$out/vid,hdvio=$out/hdvio"
ov_runner=${TMPDIR:-/tmp}/openvins-build/bin/run_asl
if [ -x "$ov_runner" ] || [ -n "${OV_GIT_DIR:-}" ]; then
  step "running OpenVINS (mono, ground-truth start) on the same images"
  if ../shared/peers/openvins/run.sh "$out/sequence" "$out/openvins/stamped_traj_estimate.txt" \
       > "$out/openvins.log" 2>&1; then
    grep -h "ms/image" "$out/openvins.log" || true
    estimates="$estimates,openvins=$out/openvins/stamped_traj_estimate.txt"
  else  # the peer is not part of the product: its column is left out with a message
    tail -n 5 "$out/openvins.log" >&2
    echo "OpenVINS column skipped: its run failed (log: $out/openvins.log)"
  fi
else
  echo "OpenVINS column skipped: not built (see ../shared/peers/openvins/README.md; set OV_GIT_DIR)"
fi

step "evaluating (posyaw-aligned ATE, RPE, velocity and force RMSE) and plotting"
"$bin/eval/hdvio_eval" --gt "$out/sequence" \
  --est "$estimates" \
  --out "$out/evaluation" --plots
echo
cat "$out/evaluation/table.md"
echo
echo "vio, vimo, vid and hdvio: the frontend on the camera images, own (static) start; openvins (if"
echo "listed): mono OpenVINS started from the ground-truth state at the first image."
echo "Force columns: each run's total non-thrust force (stamped_total_force_estimate.csv: for vimo"
echo "and vid their external force, which absorbs all non-thrust force; for hdvio its model's"
echo "force (drag law + TCN) plus its external force) against the simulator's drag + external force."
step "done: results, table and figures in $out/ (evaluation/table.md, evaluation/*.png)"
