#!/usr/bin/env bash
# Installs, from Debian's package registry, everything QualMesh needs to build, run and test. Idempotent: packages
# already present are not touched. Needs root (or sudo) only when something is missing.
set -euo pipefail

# Build: compiler, CMake, CGAL (+Boost, GMP, MPFR), CLI11, GoogleTest.
BUILD_PACKAGES="cmake g++ make libcgal-dev libboost-dev libgmp-dev libmpfr-dev libcli11-dev libgtest-dev libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev libzip-dev libjemalloc-dev"
# Tests: Debian's python3 with pytest, numpy and meshio (independent readers), the peer tools whose output the
# tests and benchmarks read or compare against, and clang with its libFuzzer runtime for the readers' fuzzing smoke
# run (scripts/fuzz.sh).
TEST_PACKAGES="python3 python3-pytest python3-numpy python3-meshio python3-gmsh python3-pygalmesh tetgen gmsh calculix-ccx openscad freecad xvfb imagemagick clang libclang-rt-dev"

want="$BUILD_PACKAGES"
if [ "${1:-}" = "--with-tests" ]; then want="$want $TEST_PACKAGES"; fi

missing=""
for p in $want; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing="$missing $p"; fi
done
if [ -z "$missing" ]; then
  echo "install-deps: all packages present"
  exit 0
fi
echo "install-deps: installing$missing"
SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
# shellcheck disable=SC2086
$SUDO apt-get install -y -q --no-install-recommends $missing
