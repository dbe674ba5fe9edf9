#!/usr/bin/env bash
# Installs the Debian 12 packages groundline needs. Idempotent: when every
# package is already installed it changes nothing and touches no network.
# Run as root (or with sudo available). Exits non-zero naming any package that
# could not be installed.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build lld
  libeigen3-dev libceres-dev
  libopencv-dev libmrcal-dev libapriltag-dev
  libv4l-dev libcamera-dev
  cyclonedds-dev cyclonedds-tools
  libcli11-dev nlohmann-json3-dev libyaml-cpp-dev libspdlog-dev libcpp-httplib-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  zlib1g-dev libbz2-dev
  clang-14 libfuzzer-14-dev
  # Tests only: the status page and the reports are checked in headless
  # Chromium (tests/integration/*_browser_test.cc skip without it).
  chromium
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: not root and no sudo; install these packages yourself: ${PACKAGES[*]}" >&2
    exit 1
  fi
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages already installed"
  exit 0
fi

echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq || { echo "setup: 'apt-get update' failed; check the network and /etc/apt/sources.list" >&2; exit 1; }
if ! $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/tmp/groundline-apt.log 2>&1; then
  # Name the packages that still are not installed, one by one.
  failed=()
  for p in "${missing[@]}"; do
    $SUDO apt-get install -y -qq --no-install-recommends "$p" >>/tmp/groundline-apt.log 2>&1 || failed+=("$p")
  done
  if [ ${#failed[@]} -ne 0 ]; then
    echo "setup: could not install: ${failed[*]} (see /tmp/groundline-apt.log)" >&2
    exit 1
  fi
fi
echo "setup: done"
