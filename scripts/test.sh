#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Quick start, tests: installs the Debian packages, builds, and runs every test (CTest:
# the C++ CppUnit suites, the gr_unittest QA of every block, the example flowgraphs).
# By default on the Release tree ./build (the one scripts/demo.sh builds). With
# SEMS_SANITIZE=address,undefined the suite runs under AddressSanitizer +
# UndefinedBehaviorSanitizer (docs/reference/hardening.md) in its own tree, ./build-sanitize: that is
# what CI runs (.ci/run); its build and test times: docs/reference/hardening.md#sanitizers.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
export SEMS_SANITIZE="${SEMS_SANITIZE-}"
if [ -n "$SEMS_SANITIZE" ]; then default_build="$root/build-sanitize"; else default_build="$root/build"; fi
export SEMS_BUILD_DIR="${SEMS_BUILD_DIR:-$default_build}"
"$root/scripts/install_deps.sh"
# A new tree compiles its largest targets in batches (the libraries, test runners, ...), as the
# demo's does (SEMS_UNITY_BUILD), so the suite also proves that the batches compile (CI's tree
# is new).
if [ ! -f "$SEMS_BUILD_DIR/CMakeCache.txt" ]; then
  export SEMS_UNITY_BUILD="${SEMS_UNITY_BUILD:-ON}"
fi
# Everything, also on a tree scripts/demo.sh configured without tests and apps.
SEMS_BUILD_TESTS=ON SEMS_BUILD_APPS=ON "$root/scripts/build.sh"
if [[ "$SEMS_SANITIZE" == *address* ]]; then
  /usr/bin/python3 "$root/scripts/check_sanitizer_env.py" "$SEMS_BUILD_DIR"
fi
# CTest runs one test per core, so each test's LibTorch gets one OpenMP thread unless the test
# sets its own count: with a thread per core in every test, the threads of two tests spin on
# each other's cores (qa_sems_learning took twice its CPU time so). The core count is read
# first: nproc honours OMP_NUM_THREADS.
jobs="$(nproc)"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
ctest --test-dir "$SEMS_BUILD_DIR" --output-on-failure -j"$jobs" "$@"
