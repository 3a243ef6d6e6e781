#!/usr/bin/env bash
# The main job: install what is missing, build, mesh the default example and check the result against its input.
# Output: out/l_bracket.vtu (open it in ParaView) and a summary on the terminal.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
./build/converters/qualmesh mesh examples/l_bracket.poly -o out/l_bracket.vtu --max-edge 0.5
./build/converters/qualmesh check out/l_bracket.vtu --ref examples/l_bracket.poly
