#!/usr/bin/env bash
# Fails (exit 1) when a library includes a header of a layer it may not depend on. The rules are
# the "depends on" column of docs/architecture.md (Layers and libraries); keep both in step:
#   core/     (hdvio_core)     core
#   core/io/  (hdvio_io)       core, io, OpenCV, HDF5
#   factors/  (hdvio_factors)  core, factors
#   frontend/ (hdvio_frontend) core, frontend, OpenCV
#   learned/  (hdvio_learned)  core, learned, libtorch (trainers behind HDVIO_WITH_TORCH)
#   backend/  (hdvio_backend)  core, factors, backend   (never learned/: std::function seams)
#   backend/pipeline/ (hdvio_pipeline) core, io, factors, frontend, learned, backend, pipeline, OpenCV
#   apps/, test/               everything
# A project header is "hdvio/<layer>/..."; OpenCV is <opencv2/...>, HDF5 <H5*.h>/<hdf5*.h>,
# libtorch <torch/...>. Usage: scripts/check_layering.sh [source-root]   (default: the repo)
set -euo pipefail
root=${1:-"$(cd "$(dirname "$0")/.." && pwd)"}
declare -A allowed=(
  [core]="core"
  [io]="core io opencv hdf5"
  [factors]="core factors"
  [frontend]="core frontend opencv"
  [learned]="core learned torch"
  [backend]="core factors backend"
  [pipeline]="core io factors frontend learned backend pipeline opencv"
)
layer_of() {  # path relative to root -> layer name, empty if not layered
  case "$1" in
    core/io/*) echo io ;;
    core/*) echo core ;;
    backend/pipeline/*) echo pipeline ;;
    factors/*|frontend/*|learned/*|backend/*) echo "${1%%/*}" ;;
    *) echo "" ;;
  esac
}
target_of() {  # an #include line -> the layer it reaches, empty if none of ours
  local line=$1
  if [[ $line =~ \#[[:space:]]*include[[:space:]]*[\"\<]hdvio/([a-z_]+)/ ]]; then echo "${BASH_REMATCH[1]}"
  elif [[ $line =~ \#[[:space:]]*include[[:space:]]*\<opencv2/ ]]; then echo opencv
  elif [[ $line =~ \#[[:space:]]*include[[:space:]]*\<(H5[A-Za-z]*|hdf5[a-z_]*)\.h ]]; then echo hdf5
  elif [[ $line =~ \#[[:space:]]*include[[:space:]]*\<torch/ ]]; then echo torch
  fi
}
cd "$root"
files=$(find core factors frontend learned backend -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cc' -o -name '*.cpp' \) 2>/dev/null | sort || true)
checked=$(printf '%s\n' "$files" | grep -c . || true)
if [ "$checked" -eq 0 ]; then echo "error: $root: no layered sources found"; exit 1; fi
violations=0
while IFS= read -r hit; do  # file:line:text
  rel=${hit%%:*}; rest=${hit#*:}; lineno=${rest%%:*}; line=${rest#*:}
  layer=$(layer_of "$rel")
  target=$(target_of "$line")
  [ -n "$layer" ] && [ -n "$target" ] || continue
  if [[ " ${allowed[$layer]} " != *" $target "* ]]; then
    echo "error: $rel:$lineno: layer '$layer' may not include '$target' (docs/architecture.md): $line"
    violations=$((violations + 1))
  fi
done < <(printf '%s\n' "$files" | xargs grep -nHE '^[[:space:]]*#[[:space:]]*include' || true)
if [ "$violations" -gt 0 ]; then echo "check_layering: $violations forbidden include(s) in $checked files"; exit 1; fi
echo "check_layering: $checked files, no forbidden include"
