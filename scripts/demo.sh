#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Quick start, demo: installs the Debian packages, builds, and streams random scenes through
# examples/sems_demo.grc — OFDM with each bundle's pilots (the classifier's learned, the delay
# estimator's random on one symbol) -> target channel -> pilot extractor -> classifier and
# delay-estimator sinks on the shipped bundles (models/classifier, models/delay_single) — at
# several SNRs. Prints the running accuracy and delay MAE of each run, then one table.
#
#   bash scripts/demo.sh [--frames N] [--snrs "0 10 20 30"] [--fast] [--no-build]
#
# --fast runs the fast bundles instead (models/classifier_fast, models/delay_single_fast:
# smaller decoders on the same pilots, see docs/PERFORMANCE.md). --no-build skips the package
# check and the build (for a second run). The build directory is $SEMS_BUILD_DIR, default
# ./build (a new one holds the module only, no tests or apps; how long the first run takes:
# docs/guides/install.md); the compiled flowgraph and the logs go to <build>/demo.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SEMS_BUILD_DIR:-$root/build}"
frames=2000
snrs="0 10 20 30"
do_build=1
suffix=""
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames="$2"; shift 2 ;;
    --snrs) snrs="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --fast) suffix=_fast; shift ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "demo.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
case "$frames" in ''|*[!0-9]*|0) echo "demo.sh: --frames must be a positive integer, got '$frames'" >&2; exit 2 ;; esac

if [ "$do_build" -eq 1 ]; then
  "$root/scripts/install_deps.sh"
  # A new tree builds only what the demo runs: the libraries, the Python package and the GRC
  # blocks, not the C++ tests and the apps (SEMS_BUILD_TESTS / SEMS_BUILD_APPS, scripts/build.sh),
  # and compiles the libraries and the core Python extension in batches
  # (SEMS_UNITY_BUILD: a faster first build). A tree configured before keeps its settings; scripts/test.sh builds
  # everything.
  if [ ! -f "$build/CMakeCache.txt" ]; then
    export SEMS_BUILD_TESTS="${SEMS_BUILD_TESTS:-OFF}" SEMS_BUILD_APPS="${SEMS_BUILD_APPS:-OFF}"
    export SEMS_UNITY_BUILD="${SEMS_UNITY_BUILD:-ON}"
  fi
  SEMS_BUILD_DIR="$build" "$root/scripts/build.sh"
fi
classifier="$root/models/classifier$suffix"
delay="$root/models/delay_single$suffix"
for bundle in "$classifier" "$delay"; do
  if [ ! -f "$bundle/bundle.json" ]; then
    echo "demo.sh: the shipped bundle $bundle is missing" >&2
    exit 1
  fi
done

out="$build/demo"
mkdir -p "$out"
export PYTHONPATH="$build/python_pkg${PYTHONPATH:+:$PYTHONPATH}"
export GRC_BLOCKS_PATH="$root/grc"
export SEMS_SOURCE_DIR="$root" # the flowgraph finds models/ here
if ! grcc -o "$out" "$root/examples/sems_demo.grc" > "$out/grcc.log" 2>&1; then
  cat "$out/grcc.log" >&2
  echo "demo.sh: grcc could not compile examples/sems_demo.grc" >&2
  exit 1
fi

for snr in $snrs; do
  echo "== SNR $snr dB, $frames frames =="
  /usr/bin/python3 -u "$out/sems_demo.py" --frames "$frames" --snr-db "$snr" \
    --classifier-bundle "$classifier" --delay-bundle "$delay" | tee "$out/snr_$snr.log"
done

echo
echo "SemS demo: $frames random-scene frames per SNR (models/classifier$suffix, models/delay_single$suffix)"
printf '%8s  %10s  %16s  %12s\n' "SNR (dB)" "accuracy" "delay MAE (idx)" "MAE (m)"
for snr in $snrs; do
  sed -n 's/^sems_demo: //p' "$out/snr_$snr.log" | tr ' ' '\n' | awk -F= '
    { v[$1] = $2 }
    END { printf "%8s  %9.1f%%  %16.3f  %12.2f\n", v["snr_db"], 100 * v["accuracy"], v["delay_mae_index"], v["delay_mae_m"] }'
done
