#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Quick start, tests: installs the Debian packages, builds, and runs every test (CTest:
# the C++ CppUnit suites, the gr_unittest QA of every block, the example flowgraphs).
# The suite runs under AddressSanitizer + UndefinedBehaviorSanitizer (docs/hardening.md):
# the module is built with -DSEMS_SANITIZE=address,undefined in its own tree,
# ./build-sanitize (scripts/demo.sh keeps its Release build in ./build). With
# SEMS_SANITIZE= (empty) the suite runs on the Release tree ./build instead.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
export SEMS_SANITIZE="${SEMS_SANITIZE-address,undefined}"
if [ -n "$SEMS_SANITIZE" ]; then default_build="$root/build-sanitize"; else default_build="$root/build"; fi
export SEMS_BUILD_DIR="${SEMS_BUILD_DIR:-$default_build}"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
ctest --test-dir "$SEMS_BUILD_DIR" --output-on-failure -j"$(nproc)" "$@"
