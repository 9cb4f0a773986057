#!/usr/bin/env bash
# Installs the Debian 12 packages debris builds with (nothing is downloaded at configure time).
# Skips apt entirely when everything is already there; uses sudo only when not root.
set -euo pipefail
packages=(
  g++ cmake make
  libeigen3-dev libhdf5-dev libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gcc-12-offload-nvptx   # the DEBRIS_OFFLOAD=nvptx configuration (GCC 12 OpenMP offload to NVIDIA GPUs)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "debris: all Debian packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "debris: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
