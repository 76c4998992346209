#!/usr/bin/env bash
# Installs the build and run-time dependencies from Debian's packages (idempotent).
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libfcl-dev libccd-dev libvtk9-dev
  libbullet-dev libbullet-extras-dev
  libopencv-dev
  python3 python3-matplotlib python3-numpy
  cyclonedds-dev cyclonedds-tools openssl
  linuxcnc-uspace linuxcnc-uspace-dev
  libimgui-dev libglfw3-dev xvfb xauth libgl1-mesa-dri
  rt-tests clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
