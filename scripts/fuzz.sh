#!/usr/bin/env bash
# Builds every libFuzzer target with clang (ASan+UBSan) in build-fuzz and runs each for a bounded time
# (OGF_FUZZ_SECONDS, default 20), starting from tests/fuzz/corpus/<name>/ when it exists. Fails when a
# target crashes or UBSan reports anything (halt_on_error: undefined behaviour such as a signed overflow is a
# failure, not a line in a log); the crashing input is left in build-fuzz/fuzz/artifacts/. Ten targets at
# 20 s each run for 3.3 min, which with the build keeps the stage within about 7 min on two cores.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${OGF_FUZZ_BUILD_DIR:-$here/build-fuzz}
seconds=${OGF_FUZZ_SECONDS:-20}
command -v clang++ >/dev/null || { echo "fuzz: clang++ not installed, skipping fuzzing"; exit 0; }
generator=()
if command -v ninja >/dev/null && [ ! -f "$build/Makefile" ]; then generator=(-G Ninja); fi
CXX=clang++ cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DOGF_BUILD_FUZZERS=ON -DOGF_BUILD_TESTS=OFF -DOGF_BUILD_BENCHMARKS=OFF >/dev/null
# (Read whole before grep: with pipefail, `grep -q` closing the pipe early fails the pipeline by SIGPIPE and
# made this skip all fuzzing at random.)
targets=$(cmake --build "$build" --target help 2>/dev/null || true)
if ! grep -q ogf_fuzzers <<<"$targets"; then
  echo "fuzz: no fuzz targets defined"; exit 0
fi
cmake --build "$build" --target ogf_fuzzers -j "${OGF_JOBS:-$(nproc)}"
mkdir -p "$build/fuzz/artifacts"
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
for target in "$build"/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  name=$(basename "$target"); name=${name#fuzz_}
  work="$build/fuzz/corpus-$name"; mkdir -p "$work"
  seeds=()
  [ -d "$here/tests/fuzz/corpus/$name" ] && seeds=("$here/tests/fuzz/corpus/$name")
  echo "fuzz: $name for ${seconds}s"
  if ! "$target" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$build/fuzz/artifacts/$name-" \
        "$work" "${seeds[@]}" >"$build/fuzz/$name.log" 2>&1; then
    echo "fuzz: $name FAILED; see $build/fuzz/$name.log"; tail -40 "$build/fuzz/$name.log"; status=1
  else
    grep -E 'stat::number_of_executed_units|stat::peak_rss_mb' "$build/fuzz/$name.log" | sed "s/^/fuzz: $name /"
  fi
done
exit $status
