#!/usr/bin/env bash
# Configures and builds ogf into build/ (programs in build/bin). Extra arguments go to cmake's configure
# step, e.g. scripts/build.sh -DOGF_SANITIZE=ON. Respects $OGF_BUILD_DIR and $OGF_JOBS.
#   scripts/build.sh [--main] [CMAKE_ARGS...]
# --main builds only the programs the main job runs (scripts/run.sh); a build directory configured here for
# the first time then leaves the tests and benchmarks out (their packages come with the test command).
# Without it, everything, tests and benchmarks included.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${OGF_BUILD_DIR:-$here/build}
jobs=${OGF_JOBS:-$(nproc)}
main_targets=(ogf-sim ogf-mapper ogf-driver ogf-map-client ogf-view ogf-replay ogf-eval ogf-map)
main=false
if [ "${1:-}" = "--main" ]; then main=true; shift; fi
generator=()
if command -v ninja >/dev/null && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
# Warnings are errors in CI (CI=true) or with OGF_WERROR=ON; otherwise the build directory keeps what it was
# configured with (changing it would rebuild everything).
werror=()
if [ "${CI:-}" = "true" ] || [ "${OGF_WERROR:-}" = "ON" ]; then werror=(-DOGF_WERROR=ON); fi
if [ "${OGF_WERROR:-}" = "OFF" ]; then werror=(-DOGF_WERROR=OFF); fi
scope=(-DOGF_BUILD_TESTS=ON -DOGF_BUILD_BENCHMARKS=ON)
targets=()
if $main; then
  scope=()
  [ -f "$build/CMakeCache.txt" ] || scope=(-DOGF_BUILD_TESTS=OFF -DOGF_BUILD_BENCHMARKS=OFF)
  targets=(--target "${main_targets[@]}")
fi
cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo ${werror[@]+"${werror[@]}"} \
  ${scope[@]+"${scope[@]}"} "$@"
cmake --build "$build" -j "$jobs" ${targets[@]+"${targets[@]}"}
