#!/usr/bin/env bash
# Installs the Debian 12 packages fvx needs to build and test; does nothing when they are
# all present. Needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config jq time gnuplot-nox
  libpcl-dev liboctomap-dev libeigen3-dev libopencv-dev nlohmann-json3-dev
  libcgal-dev libembree-dev liburdfdom-dev libtinyxml-dev liborocos-kdl-dev libnanoflann-dev
  librosbag-storage-dev libsensor-msgs-dev libtf2-msgs-dev libtf2-dev  # ROS 1 bags, without ROS
  libgtest-dev libgmock-dev libbenchmark-dev
  parallel slurm-wlm munge  # fvx batch plans run by GNU parallel and by a local Slurm (tests)
  openssh-server openssh-client  # ... and by GNU parallel on a host reached by ssh (a local sshd, tests)
  clang libclang-rt-dev llvm  # scripts/sanitize.sh and scripts/fuzz.sh: ASan, UBSan, libFuzzer, symbolizer
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
