#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the unit and property tests under AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan/; the real-model meshing suites RealModels*, PumpReal, CadMeshes* and ScadMeshes* take
# minutes each there, so they run in the Release build only) and the hostile catalogue against the sanitizer build
# of the CLI, a fuzzing smoke run of the readers, then the whole suite in the Release build (build/).
# CTest's closing summary of the Release run is the last thing printed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --with-tests
jobs=$(nproc 2>/dev/null || echo 2)

echo "== sanitizer build (ASan + UBSan) =="
# -O1 rather than RelWithDebInfo's -O2: the build is most of CI's time (its CGAL-heavy units), and -O1 takes 22% less
# CPU to compile it (26.5 against 34.8 min, 2 cores) while its unit tests run 7% longer (212 against 198 s).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DQUALMESH_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" >/dev/null
cmake --build build-asan -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions="$PWD/tests/sanitizer/lsan.supp" \
  ctest --test-dir build-asan -L cpp -E "RealModels|PumpReal|CadMeshes|ScadMeshes" --output-on-failure -j"$jobs"
# The whole hostile catalogue (tests/hostile/) against the sanitizer build of the CLI too (about 30 s).
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions="$PWD/tests/sanitizer/lsan.supp" \
  ctest --test-dir build-asan -R "^py_test_hostile$" --output-on-failure

# A short fuzzing smoke run of every reader (tests/fuzz/, scripts/fuzz.sh; clang build in build-fuzz/): 12 s each,
# about 3 minutes with the build; any crash, sanitizer report, uncaught exception or hang fails the run.
echo "== fuzzing smoke run (libFuzzer, 12 s per reader) =="
bash scripts/fuzz.sh all 12

echo "== release build, full suite =="
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j"$jobs"
