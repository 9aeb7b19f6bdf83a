#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/*_fuzz.cpp) with clang and runs each for a bounded
# time, seeded from tests/fuzz/corpus/<target>/ and ../shared/refdata where the target says so.
#   scripts/fuzz.sh [SECONDS_PER_TARGET]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shopt -s nullglob
targets=(tests/fuzz/*_fuzz.cpp)
if [ ${#targets[@]} -eq 0 ]; then echo "fuzz.sh: no fuzz targets"; exit 0; fi
CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DARDCELL_FUZZ=ON -DARDCELL_BUILD_TESTS=OFF -DARDCELL_BUILD_BENCH=OFF -DARDCELL_NATIVE=OFF \
  >/dev/null
for src in "${targets[@]}"; do
  name=$(basename "$src" .cpp)
  cmake --build build/fuzz --target "$name" -j "$(nproc)"
  work=build/fuzz/corpus-$name
  mkdir -p "$work"
  seeds=()
  [ -d "tests/fuzz/corpus/$name" ] && seeds+=("tests/fuzz/corpus/$name")
  echo "fuzz.sh: $name for ${seconds}s"
  "build/fuzz/$name" -max_total_time="$seconds" -print_final_stats=1 "$work" "${seeds[@]}" \
    2>&1 | tail -n 12
done
