#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Configures and builds gr-sems into $SEMS_BUILD_DIR, default ./build (Release). GNU Radio's
# Python is /usr/bin/python3. SEMS_SANITIZE (e.g. address,undefined) builds with sanitizers.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEMS_BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DSEMS_SANITIZE="${SEMS_SANITIZE:-}"
cmake --build "$build" -j"$(nproc)"
