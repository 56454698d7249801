#!/usr/bin/env bash
# Configures and builds ogf into build/ (programs in build/bin). Extra arguments go to cmake's configure
# step, e.g. scripts/build.sh -DOGF_SANITIZE=ON. Respects $OGF_BUILD_DIR and $OGF_JOBS.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${OGF_BUILD_DIR:-$here/build}
jobs=${OGF_JOBS:-$(nproc)}
generator=()
if command -v ninja >/dev/null && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
werror=OFF
if [ "${CI:-}" = "true" ] || [ "${OGF_WERROR:-}" = "ON" ]; then werror=ON; fi
cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOGF_WERROR=$werror "$@"
cmake --build "$build" -j "$jobs"
