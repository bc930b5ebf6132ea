#!/usr/bin/env bash
# Installs every Debian 12 package Pliant builds, tests or runs with.
# Skips what is present; safe to run twice. Needs root (or sudo) only when
# something is missing.
set -euo pipefail

ENGINE_PKGS=(build-essential cmake ninja-build pkg-config git
  libeigen3-dev libsuitesparse-dev nlohmann-json3-dev libcli11-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev libomp-dev
  clang libclang-rt-14-dev fonts-dejavu-core liblbfgspp-dev libassimp-dev
  libmujoco-dev libmujoco-samples libopenvdb-dev libompl-dev ffmpeg)
EDITOR_PKGS=(libimgui-dev libglfw3-dev libegl-dev libegl1-mesa-dev libgl-dev
  libgl1-mesa-dri libgles-dev xvfb xauth)

want=("${ENGINE_PKGS[@]}")
if [ "${PLIANT_EDITOR:-ON}" != "OFF" ]; then want+=("${EDITOR_PKGS[@]}"); fi

missing=()
for p in "${want[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#want[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
