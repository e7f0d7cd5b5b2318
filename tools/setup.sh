#!/usr/bin/env bash
# Installs exactly the Debian 12 packages sinew needs that are missing.
# Idempotent; prints nothing when everything is already there.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libembree-dev libccd-dev libsuitesparse-dev libtbb-dev
  nlohmann-json3-dev doctest-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libgles-dev
  libimgui-dev libstb-dev
  ffmpeg
  # Optimised single-threaded BLAS for CHOLMOD's supernodal factorisation (16x faster than
  # the reference BLAS on a 10k-hex lattice); serial, so it never competes with oneTBB.
  libopenblas0-serial
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}" >&2
if [[ $(id -u) -ne 0 ]]; then
  echo "setup: must run as root to install packages (try: sudo $0)" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done" >&2
