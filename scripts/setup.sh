#!/usr/bin/env bash
# Installs the Debian packages hdvio needs. Idempotent: packages already present are skipped.
# Usage: scripts/setup.sh [--with-torch] [--with-openvins] [--with-fuzz]
#   --with-torch adds libtorch for the trainer; --with-fuzz clang-14 and libFuzzer (scripts/fuzz.sh);
#   --with-openvins the Boost parts the OpenVINS peer of config/bench/sim_images.yaml needs, built by
#   ../shared/peers/openvins/build.sh (docs/bench.md "Peers")
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libceres-dev libsuitesparse-dev
  libgoogle-glog-dev libgflags-dev libyaml-cpp-dev nlohmann-json3-dev
  libopencv-dev
  libhdf5-dev
  libbz2-dev liblz4-dev
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-pil
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib
)
for arg in "$@"; do
  case "$arg" in
    --with-torch) packages+=(libtorch-dev) ;;
    --with-openvins)
      packages+=(libboost-system-dev libboost-filesystem-dev libboost-thread-dev libboost-date-time-dev) ;;
    --with-fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    *) echo "setup.sh: unknown argument '$arg' (expected --with-torch, --with-openvins or --with-fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup.sh: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "setup.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
