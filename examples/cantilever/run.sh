#!/usr/bin/env bash
# The cantilever from STEP to CalculiX in three commands: mesh the part with second-order tetrahedra, run the deck
# that includes the mesh, read the tip deflection. Run from anywhere: bash examples/cantilever/run.sh
# QUALMESH (default: qualmesh on PATH, else the build tree's) and CCX (default: ccx) choose the programs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
qualmesh="${QUALMESH:-$(command -v qualmesh || echo "$here/../../build/converters/qualmesh")}"
work="${WORK:-$(mktemp -d)}"
cp "$here/beam.step" "$here/cantilever.inp" "$work/"
cd "$work"
"$qualmesh" mesh beam.step --order 2 --size 8 -o beam.inp
"${CCX:-ccx}" -i cantilever > ccx.log
# The .dat file lists the displacement (ux, uy, uz) of every node of Face2 after its header: print their mean uy.
awk '/displacements/ {found = 1; next} found && NF == 4 {sum += $3; n++}
     END {if (n == 0) exit 1; printf "tip deflection (mean over the %d nodes of Face2): %.4f mm\n", n, -sum / n}' cantilever.dat
echo "results in $work (cantilever.frd opens in cgx or ParaView through meshio)"
