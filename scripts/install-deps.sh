#!/usr/bin/env bash
# Installs the Debian packages ogf needs: with --main only what the main job's programs need (scripts/run.sh),
# else everything to build, test and run. Idempotent: when all packages are present it only checks and exits.
# Run as root (or with sudo available).
set -euo pipefail

# What the main job (scripts/run.sh) needs to build and run its programs.
MAIN_PACKAGES=(
  build-essential cmake pkg-config ninja-build
  # messages: LCM 1.3.1 (C/C++ library, lcm-gen)
  liblcm-dev liblcm-bin
  # libraries the code uses
  zlib1g-dev libpcap-dev libsodium-dev libsqlite3-dev libeigen3-dev libboost-dev libspdlog-dev libyaml-cpp-dev libcli11-dev
  # MCAP chunks: Zstandard and LZ4 frames
  libzstd-dev liblz4-dev
  # ogf-view's page: three.js, served from /usr/share/javascript/three (Boost.Beast is in libboost-dev)
  libjs-three
  # ogf-eval's baseline and the .bt exports
  liboctomap-dev
  # scripts/multicast-loopback.sh (ip route)
  iproute2
)
# What the tests, the benchmarks, lcm-spy and the Python package need besides.
TEST_PACKAGES=(
  # the lcm types' Java jar and lcm-spy (default-jre: lcm-spy opens a window; the headless JDK builds the jar)
  liblcm-java default-jdk-headless default-jre libjchart2d-java
  libgtest-dev libgmock-dev libbenchmark-dev
  # ogf-view's browser test: headless Chromium (WebGL on SwiftShader)
  chromium
  # the MCAP and Foxglove tests run the reference libraries (npm packages pinned in tests/foxglove) on Node.js
  nodejs
  # fuzzing (clang's libFuzzer runtime) and tooling used by the tests (wireshark-common: editcap writes
  # the pcapng copy of a real capture that the capture reader's pcapng test reads)
  clang libclang-rt-14-dev unzip python3 wireshark-common
  # the Python package (python/, pybind11) and the Python tests: numpy arrays, pytest, Pillow and PyYAML as
  # the independent readers of the navigation grid's files, matplotlib for the examples in docs/python.md
  pybind11-dev python3-dev python3-numpy python3-pytest python3-pil python3-yaml python3-matplotlib
  # packaging: cpack's Depends (dpkg-shlibdeps), the package check, the clean Debian 12 to install it in
  dpkg-dev lintian debootstrap
)
PACKAGES=("${MAIN_PACKAGES[@]}")
if [ "${1:-}" = "--main" ]; then
  shift
else
  PACKAGES+=("${TEST_PACKAGES[@]}")
fi
if [ $# -gt 0 ]; then echo "install-deps: unknown argument '$1' (only --main)" >&2; exit 2; fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Debian's npm, unless the installed nodejs brings its own (a nodejs package that bundles npm conflicts with it).
if [ ${#PACKAGES[@]} -gt ${#MAIN_PACKAGES[@]} ]; then command -v npm >/dev/null || missing+=(npm); fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
