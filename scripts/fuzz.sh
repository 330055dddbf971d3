#!/usr/bin/env bash
# Coverage-guided fuzzing of the case parser and validation with libFuzzer (clang), for as long
# as you like; CTest runs the deterministic harness (fuzz_cases) for a bounded time instead.
#   scripts/fuzz.sh [SECONDS]     (default 3600; 0 = until stopped)
# Builds build-fuzz/ with clang, ASan and UBSan, seeds the corpus with cases/ and
# tests/fuzz/corpus/, and keeps new inputs in build-fuzz/corpus and crashes in build-fuzz/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-3600}
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DPCSIM_FUZZ=ON >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_cases_libfuzzer
mkdir -p build-fuzz/corpus
cp cases/*.toml tests/fuzz/corpus/*.toml build-fuzz/corpus/ 2>/dev/null || true
args=(-max_len=65536 -artifact_prefix=build-fuzz/)
[ "$seconds" != 0 ] && args+=(-max_total_time="$seconds")
exec build-fuzz/fuzz_cases_libfuzzer "${args[@]}" build-fuzz/corpus
