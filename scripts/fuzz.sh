#!/usr/bin/env bash
# Fuzzes one reader for a set time: scripts/fuzz.sh READER SECONDS [extra libFuzzer flags]
#   READER: poly smesh node off stl obj medit (PLC readers), vtu msh inp unv mesh_medit mesh_tetgen (check's mesh
#           readers); "all" runs each in turn for SECONDS.
# Builds the harnesses in build-fuzz/ with clang (-DQUALMESH_FUZZ=ON; tests/fuzz/CMakeLists.txt) when needed, then
# runs build-fuzz/fuzz/fuzz_READER on one core, single process, seeded from tests/fuzz/corpus/READER (read only: new
# inputs go to build-fuzz/corpus/READER). A crash, sanitizer report, uncaught exception, hang (> 10 s per input) or
# blow-up (> 2 GB) is a finding: its input is saved in build-fuzz/findings/READER/ and the script exits 1. Make each
# finding a regression test: copy it into tests/fuzz/regressions/READER/ (test_fuzz_regressions.py runs them all).
# Minimise the new inputs into the committed corpus with: scripts/fuzz.sh --merge READER
set -euo pipefail
cd "$(dirname "$0")/.."
READERS="poly smesh node off stl obj medit vtu msh inp unv mesh_medit mesh_tetgen"

build() {
  if [ ! -f build-fuzz/CMakeCache.txt ]; then
    CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release -DQUALMESH_FUZZ=ON \
      -DQUALMESH_BUILD_TESTS=OFF >/dev/null
  fi
  cmake --build build-fuzz -j"$(nproc 2>/dev/null || echo 2)" --target "$@" >build-fuzz/build.log 2>&1 ||
    { tail -30 build-fuzz/build.log >&2; exit 1; }
}

if [ "${1:-}" = "--merge" ]; then
  reader=$2
  build "fuzz_$reader"
  mkdir -p "build-fuzz/merged/$reader"
  rm -rf "build-fuzz/merged/$reader"/*
  ./build-fuzz/fuzz/fuzz_"$reader" -merge=1 -max_len=16384 "build-fuzz/merged/$reader" "tests/fuzz/corpus/$reader" \
    "build-fuzz/corpus/$reader" 2>&1 | tail -1
  rm -rf "tests/fuzz/corpus/$reader"
  cp -r "build-fuzz/merged/$reader" "tests/fuzz/corpus/$reader"
  echo "fuzz: tests/fuzz/corpus/$reader: $(ls "tests/fuzz/corpus/$reader" | wc -l) inputs, $(du -sb "tests/fuzz/corpus/$reader" | cut -f1) bytes"
  exit 0
fi

if [ $# -lt 2 ]; then
  echo "usage: scripts/fuzz.sh READER SECONDS [libFuzzer flags] | --merge READER  (readers: $READERS, all)" >&2
  exit 2
fi
reader=$1
seconds=$2
shift 2
if [ "$reader" = "all" ]; then
  status=0
  for r in $READERS; do bash "$0" "$r" "$seconds" "$@" || status=1; done
  exit $status
fi
case " $READERS " in *" $reader "*) ;; *) echo "fuzz: unknown reader '$reader' (known: $READERS)" >&2; exit 2 ;; esac

build "fuzz_$reader"
mkdir -p "build-fuzz/corpus/$reader" "build-fuzz/findings/$reader"
log="build-fuzz/findings/$reader/last.log"
start=$(date +%s)
set +e
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ./build-fuzz/fuzz/fuzz_"$reader" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="build-fuzz/findings/$reader/" "$@" \
  "build-fuzz/corpus/$reader" "tests/fuzz/corpus/$reader" >"$log" 2>&1
rc=$?
set -e
runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
echo "fuzz: $reader: $(( $(date +%s) - start )) s, $runs inputs, $cov, exit $rc"
if [ $rc -ne 0 ]; then
  grep -E "ERROR|SUMMARY|Test unit written|terminate called|what\(\)" "$log" | head -20 >&2
  exit 1
fi
