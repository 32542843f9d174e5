#!/usr/bin/env bash
# Builds the libFuzzer reader targets (test/fuzz, clang-14 + ASan/UBSan) in build-fuzz/ and runs
# each for a bounded time. Not part of CI. docs/fuzzing.md lists the targets and past results.
# Usage: scripts/fuzz.sh [--minutes N] [--parallel P] [target...]
#   --minutes N   time per target (default 10), libFuzzer's -max_total_time
#   --parallel P  targets run at once (default 2; the machine has 2 cores)
#   target        fuzz_asl_csv fuzz_sensor_yaml fuzz_ros_bag fuzz_ros_messages fuzz_hdf5_datasets
#                 fuzz_hdf5_raw fuzz_tcn_weights (default: all)
# Crashes, hangs and out-of-memory inputs go to build-fuzz/crashes/<target>/; the growing corpus
# to build-fuzz/corpus/<target>/ (kept between runs). Exits 1 if any target found one.
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=10
parallel=2
targets=()
all=(fuzz_asl_csv fuzz_sensor_yaml fuzz_ros_bag fuzz_ros_messages fuzz_hdf5_datasets fuzz_hdf5_raw fuzz_tcn_weights)
while [[ $# -gt 0 ]]; do
  case "$1" in
    --minutes) minutes="$2"; shift 2 ;;
    --parallel) parallel="$2"; shift 2 ;;
    fuzz_*) targets+=("$1"); shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (expected --minutes N, --parallel P or a fuzz_* target)" >&2; exit 2 ;;
  esac
done
[[ ${#targets[@]} -gt 0 ]] || targets=("${all[@]}")
[[ "$minutes" =~ ^[0-9]+$ && "$minutes" -gt 0 ]] || { echo "fuzz.sh: --minutes needs a positive integer" >&2; exit 2; }
bash scripts/setup.sh --with-fuzz

build=build-fuzz
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 \
  -DCMAKE_CXX_COMPILER=clang++-14 "${launcher[@]}" -DHDVIO_BUILD_FUZZERS=ON -DHDVIO_BUILD_TESTS=OFF >/dev/null
nice cmake --build "$build" -j2 --target "${targets[@]}" fuzz_make_seeds

# Seeds: small valid files written by the project's writers, plus the first rows of the shared
# EuRoC excerpt; generated at run time outside the repository.
seeds=$(mktemp -d /tmp/hdvio_fuzz_seeds.XXXXXX)
started=$(mktemp /tmp/hdvio_fuzz_started.XXXXXX)  # findings of this run only: crashes/ keeps older ones
trap 'rm -rf "$seeds" "$started"' EXIT
"$build/test/fuzz/fuzz_make_seeds" "$seeds" "../shared/data/euroc/V1_01_easy_excerpt"

run_one() {
  local t=$1 crashes="$build/crashes/$1" corpus="$build/corpus/$1" log="$build/logs/$1.log"
  mkdir -p "$crashes" "$corpus" "$seeds/$t" "$(dirname "$log")"
  local committed=()
  [[ -d test/fuzz/seeds/$t ]] && committed=("test/fuzz/seeds/$t")
  # libhdf5 leaks its own allocations on some corrupt files (no project frame in the report,
  # docs/fuzzing.md): leaks are not checked where libhdf5's parser is the target.
  # Its metadata cache also tries allocations of ~2^64 bytes for corrupt sizes and handles the
  # failure (an error, exit 2, in a normal build): there ASan returns null instead of aborting.
  local extra=()
  local asan="${ASAN_OPTIONS:-}"
  [[ $t == fuzz_hdf5_raw ]] && extra=(-detect_leaks=0) && asan="allocator_may_return_null=1${asan:+:$asan}"
  # Every HDF5 input forks the fuzzer (hdf5_snapshot.h) and a fork costs in proportion to the
  # resident size: ASan's 256 MiB default quarantine made it ~2 inputs/s, 8 MiB gives ~30/s.
  [[ $t == fuzz_hdf5_* ]] && asan="quarantine_size_mb=8${asan:+:$asan}"
  # -malloc_limit_mb: no input of a few KiB may make a reader allocate 512 MiB at once.
  ASAN_OPTIONS="$asan" nice "$build/test/fuzz/$t" -max_total_time=$((minutes * 60)) -rss_limit_mb=2048 -malloc_limit_mb=512 \
    -timeout=10 -print_final_stats=1 "${extra[@]}" -artifact_prefix="$crashes/" "$corpus" "$seeds/$t" "${committed[@]}" \
    >"$log" 2>&1 || true
}

running=0
for t in "${targets[@]}"; do
  run_one "$t" &
  running=$((running + 1))
  if [[ $running -ge $parallel ]]; then wait -n || true; running=$((running - 1)); fi
done
wait

found=0
printf '%-20s %12s %8s %8s %8s %s\n' target executions exec/s cov ft crashes
for t in "${targets[@]}"; do
  log="$build/logs/$t.log"
  runs=$(awk '/^stat::number_of_executed_units:/ {v = $2} END {print v}' "$log")
  speed=$(awk '/^stat::average_exec_per_sec:/ {v = $2} END {print v}' "$log")
  cov=$( (grep -o 'cov: [0-9]*' "$log" || true) | tail -1 | awk '{print $2}')  # none if it died at once
  ft=$( (grep -o 'ft: [0-9]*' "$log" || true) | tail -1 | awk '{print $2}')
  n=$(find "$build/crashes/$t" -type f -newer "$started" \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' \) | wc -l)
  printf '%-20s %12s %8s %8s %8s %s\n' "$t" "${runs:-?}" "${speed:-?}" "${cov:-?}" "${ft:-?}" "$n"
  # The HDF5 readers run libhdf5 in a child process (core/io/src/hdf5_snapshot.h): its crashes
  # on damaged files are InputErrors, not findings, but ASan's reports of them land in the log.
  child=$(grep -c 'ERROR: AddressSanitizer' "$log" || true)
  [[ $n -eq 0 && ${child:-0} -gt 0 ]] && echo "  $t: $child ASan reports from libhdf5's child process (handled as InputErrors)"
  if [[ $n -gt 0 || -z "$runs" ]]; then
    found=1
    grep -m1 -E 'ERROR: (AddressSanitizer|libFuzzer)|runtime error|==ERROR|uncaught|terminate called|abort' "$log" | sed "s/^/  $t: /" || true
  fi
done
[[ $found -eq 0 ]] || { echo "fuzz.sh: see $build/crashes/ and $build/logs/"; exit 1; }
