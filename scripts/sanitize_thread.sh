#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ThreadSanitizer run (docs/reference/hardening.md): builds the learning library and the CppUnit
# runner qa_sems_threads with -DSEMS_SANITIZE=thread in their own tree and runs qa_thread_access, which
# calls every setter and getter of every C++ block from another thread while three
# flowgraphs stream (frequency domain: mapper -> channel -> extractors -> both sinks and
# the range-Doppler map; time domain: mapper -> IFFT -> target_channel_td -> frame_sync, and
# -> leakage canceller -> CFO corrector, beside a phase-noise source; an array: mapper ->
# 8-element channel -> extractor -> position sink and range-angle map).
# Fails on the first data race in our code (halt_on_error). GNU Radio, LibTorch and Boost
# are not instrumented: cmake/tsan.supp lists, with the reason, what is provably not ours.
#
#   bash scripts/sanitize_thread.sh [repeats]     (default 3 runs of the test)
#
# The build directory is $SEMS_TSAN_BUILD_DIR, default ./build-tsan.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEMS_TSAN_BUILD_DIR:-$root/build-tsan}"
repeats="${1:-3}"
case "$repeats" in ''|*[!0-9]*|0) echo "sanitize_thread.sh: repeats must be a positive integer, got '$repeats'" >&2; exit 2 ;; esac
mkdir -p "$build"
# The libraries in batches (SEMS_UNITY_BUILD), as the sanitized suite's tree: a third of the
# learning library's file-by-file compile time, less than half of the core's (docs/guides/install.md).
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 -DSEMS_SANITIZE=thread \
  -DSEMS_UNITY_BUILD=ON > "$build/configure.log" 2>&1 \
  || { cat "$build/configure.log" >&2; exit 1; }
cmake --build "$build" -j"${SEMS_BUILD_JOBS:-2}" --target qa_sems_threads
# No ifunc resolver may be left in what the test loads: the loader runs it before the TSan
# runtime is up (lib/core/kernels/cpu_dispatch.h). An IFUNC symbol or IRELATIVE relocation here means
# a function was cloned without SEMS_TARGET_CLONES.
for f in "$build"/lib/libgnuradio-sems*.so "$build/lib/learning/qa_sems_threads"; do
  if readelf -W --syms --relocs "$f" | grep -E "IFUNC|IRELATIV"; then
    echo "sanitize_thread.sh: $f has an ifunc resolver built with ThreadSanitizer (see lib/core/kernels/cpu_dispatch.h)" >&2
    exit 1
  fi
done
export SEMS_SOURCE_DIR="$root"
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$root/cmake/tsan.supp"
for i in $(seq 1 "$repeats"); do
  echo "== sanitize_thread.sh: run $i of $repeats =="
  "$build/lib/learning/qa_sems_threads" qa_thread_access
done
echo "sanitize_thread.sh: $repeats runs, no data race reported"
