#!/usr/bin/env bash
# The main job: install what is missing, build, and run QualMesh on the default example.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/converters/qualmesh info examples/l_bracket.poly
