#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Quick start, tests: installs the Debian packages, builds, and runs every test (CTest:
# the C++ CppUnit suites, the gr_unittest QA of every block, the example flowgraphs).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
ctest --test-dir "${SEMS_BUILD_DIR:-$root/build}" --output-on-failure -j"$(nproc)" "$@"
