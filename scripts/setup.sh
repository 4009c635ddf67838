#!/usr/bin/env bash
# Installs the Debian packages bridgefit needs, only those that are missing.
# Idempotent: prints "all dependencies present" and changes nothing when done.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libeigen3-dev libnlopt-cxx-dev libceres-dev libopencv-dev libhdf5-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libtomlplusplus-dev libmatio-dev libspdlog-dev libfmt-dev nlohmann-json3-dev
  gnuplot-nox hdf5-tools python3-h5py chromium
  libopenmpi-dev openmpi-bin
)
# Optional extras (e.g. chromium for the report test): BRIDGEFIT_EXTRA_PACKAGES="chromium"
if [[ -n "${BRIDGEFIT_EXTRA_PACKAGES:-}" ]]; then
  read -r -a extra <<< "${BRIDGEFIT_EXTRA_PACKAGES}"
  PACKAGES+=("${extra[@]}")
fi

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all dependencies present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo > /dev/null; then SUDO="sudo"; else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
