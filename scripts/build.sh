#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Configures and builds gr-sems into $SEMS_BUILD_DIR, default ./build (Release). GNU Radio's
# Python is /usr/bin/python3. SEMS_SANITIZE (e.g. address,undefined) builds with sanitizers.
# SEMS_BUILD_TESTS / SEMS_BUILD_APPS (ON/OFF, default: the tree's setting, ON for a new tree)
# build the C++ test runners and the apps (sems_train, sems_eval, benchmarks) or leave them out;
# scripts/demo.sh leaves both out on a new tree (the demo runs neither). SEMS_UNITY_BUILD (ON/OFF,
# default: the tree's setting, OFF for a new tree) compiles the libraries, the largest runners and the core
# Python extension in batches: a faster first build, slower rebuilds (scripts/demo.sh: ON).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEMS_BUILD_DIR:-$root/build}"
options=()
for opt in SEMS_BUILD_TESTS SEMS_BUILD_APPS SEMS_UNITY_BUILD; do
  [ -z "${!opt:-}" ] || options+=("-D$opt=${!opt}")
done
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DSEMS_SANITIZE="${SEMS_SANITIZE:-}" "${options[@]}"
cmake --build "$build" -j"$(nproc)"
