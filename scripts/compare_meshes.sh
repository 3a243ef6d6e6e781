#!/usr/bin/env bash
# Meshes a fixed set of inputs with two qualmesh binaries and compares the output files byte for byte: the check
# that a refactoring of the engine (issue 16, "rebuild the engine as levels") changed no mesh. Not a CI test: it
# needs a baseline binary built from an earlier commit.
#
# Usage: scripts/compare_meshes.sh BASELINE NEW [SHARED_DIR] [OUT_DIR]
#   BASELINE, NEW  qualmesh executables (a CAD plugin, libqualmesh_cad_plugin.so, must lie beside each one for the
#                  CAD case, as the CLI looks for it there);
#   SHARED_DIR     the shared/ folder with data/plc and data/cad (default: ../shared beside the repository);
#   OUT_DIR        where both meshes of each case are written (default: a fresh temporary folder).
# Cases: the PLC models of SHARED_DIR/data/plc that mesh in under 20 s, the inputs of examples/ and
# tests/data/small, each with the default options, --no-pump and --encroaching steiner, and the CAD file
# data/cad/part.step with the default options. A CAD file is first converted to a PLC by each binary's CAD front
# end (`qualmesh convert`); when the two PLCs differ (the front end changed, not the engine), the line says so and
# both binaries mesh the baseline's PLC instead, which compares the engine alone.
# When NEW knows --no-improve (the post-extraction improvement pass), NEW runs with it, so that both binaries run
# the same engine stages. Prints one line per case and exits 1 when any output differs or a run fails in one
# binary only.
set -u
if [ $# -lt 2 ]; then
  sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
BASELINE=$(readlink -f "$1")
NEW=$(readlink -f "$2")
REPO=$(cd "$(dirname "$0")/.." && pwd)
SHARED=${3:-$REPO/../shared}
OUT=${4:-$(mktemp -d /tmp/compare_meshes.XXXXXX)}
mkdir -p "$OUT/baseline" "$OUT/new"

NEW_EXTRA=()
if "$NEW" mesh --help 2>&1 | grep -q -- '--no-improve'; then NEW_EXTRA=(--no-improve); fi

# PLC models (data/plc) that mesh in under 20 s with the default options (timed at commit 19531c3). Not here:
# aorta2.stl and elephant.mesh (open surfaces, refused), cow.off (self-intersecting, refused), bunny00.off,
# cheese.off and turbine.off (over 20 s).
PLC_MODELS=(example.poly wedge-1.smesh spike-1-10.smesh slit-1.smesh cubes.off anchor.off joint.off
            couplingdown.off elephant.off fandisk.off pinion.off lever.stl t13_data.stl)
INPUTS=()
for m in "${PLC_MODELS[@]}"; do INPUTS+=("$SHARED/data/plc/$m"); done
INPUTS+=("$REPO/examples/l_bracket.poly")
for f in "$REPO"/tests/data/small/*; do INPUTS+=("$f"); done

OPTION_SETS=("" "--no-pump" "--encroaching steiner")

num_same=0 num_differ=0 num_failed=0
run_case() {  # name, input, options...
  local name=$1 input=$2
  shift 2
  local base_out="$OUT/baseline/$name.vtu" new_out="$OUT/new/$name.vtu"
  local t0 t1 t2 rc_base rc_new
  t0=$(date +%s.%N)
  "$BASELINE" mesh "$input" -o "$base_out" "$@" >"$OUT/baseline/$name.log" 2>&1
  rc_base=$?
  t1=$(date +%s.%N)
  "$NEW" mesh "$input" -o "$new_out" "$@" "${NEW_EXTRA[@]}" >"$OUT/new/$name.log" 2>&1
  rc_new=$?
  t2=$(date +%s.%N)
  local times
  times=$(awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN { printf "%6.2fs %6.2fs", b - a, c - b }')
  if [ $rc_base -ne 0 ] || [ $rc_new -ne 0 ]; then
    if [ $rc_base -eq $rc_new ] && [ ! -e "$base_out" ] && [ ! -e "$new_out" ]; then
      printf '%-44s both refused (exit %d)   %s\n' "$name" $rc_base "$times"
      num_same=$((num_same + 1))
    else
      printf '%-44s FAILED (exit %d / %d)     %s\n' "$name" $rc_base $rc_new "$times"
      num_failed=$((num_failed + 1))
    fi
    return
  fi
  if cmp -s "$base_out" "$new_out"; then
    printf '%-44s identical %10s bytes  %s\n' "$name" "$(stat -c %s "$new_out")" "$times"
    num_same=$((num_same + 1))
  else
    printf '%-44s DIFFER                   %s\n' "$name" "$times"
    num_differ=$((num_differ + 1))
  fi
}

echo "baseline: $BASELINE"
echo "new:      $NEW ${NEW_EXTRA[*]}"
echo "outputs:  $OUT"
for input in "${INPUTS[@]}"; do
  if [ ! -e "$input" ]; then
    echo "missing input: $input" >&2
    num_failed=$((num_failed + 1))
    continue
  fi
  for opts in "${OPTION_SETS[@]}"; do
    tag=${opts//--/}
    tag=${tag// /-}
    # shellcheck disable=SC2086  # the option set is split into words on purpose
    run_case "$(basename "$input")${tag:+.$tag}" "$input" $opts
  done
done
# CAD: name, input, options...
run_cad_case() {
  local name=$1 input=$2
  shift 2
  "$BASELINE" convert "$input" "$OUT/baseline/$name.poly" >/dev/null 2>&1
  "$NEW" convert "$input" "$OUT/new/$name.poly" >/dev/null 2>&1
  if cmp -s "$OUT/baseline/$name.poly" "$OUT/new/$name.poly"; then
    run_case "$name" "$input" "$@"
  else
    printf '%-44s the CAD front ends give different PLCs: the baseline'"'"'s PLC instead\n' "$name"
    run_case "$name.baseline-plc" "$OUT/baseline/$name.poly" "$@"
  fi
}
for opts in "${OPTION_SETS[@]}"; do
  tag=${opts//--/}
  tag=${tag// /-}
  # shellcheck disable=SC2086
  run_cad_case "beam.step${tag:+.$tag}" "$REPO/examples/cantilever/beam.step" $opts
done
run_cad_case "part.step" "$SHARED/data/cad/part.step"

echo "identical: $num_same, differ: $num_differ, failed: $num_failed"
[ $num_differ -eq 0 ] && [ $num_failed -eq 0 ]
