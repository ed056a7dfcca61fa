#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the libFuzzer harnesses in fuzz/ (clang, ASan+UBSan, torch-free sources only)
# and runs each for SECONDS seconds (default 60) on its seed corpus, as many at once as there
# are cores (each harness is one process on one core; $SEMS_FUZZ_JOBS overrides the count).
# Exit status 1 when a harness finds a crash; the reproducer is left in
# $SEMS_FUZZ_BUILD_DIR/artifacts/<harness>/ and the log in $SEMS_FUZZ_BUILD_DIR/fuzz_<harness>.log.
#
#   scripts/fuzz.sh              # 60 s each
#   scripts/fuzz.sh 25           # what CI runs
#   scripts/fuzz.sh 600          # 10 minutes each
#   scripts/fuzz.sh 600 scene    # one harness
# Every fuzz/fuzz_<name>.cc is a harness <name>, seeded from fuzz/corpus/<name>/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
shift || true
if [[ ! "$seconds" =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz.sh: SECONDS must be a positive integer, got '$seconds'" >&2
  exit 2
fi
if [[ $# -gt 0 ]]; then
  harnesses=("$@")
else
  harnesses=()
  for f in "$root"/fuzz/fuzz_*.cc; do h="$(basename "$f" .cc)"; harnesses+=("${h#fuzz_}"); done
fi
build="${SEMS_FUZZ_BUILD_DIR:-$root/build-fuzz}"
cxx="${SEMS_FUZZ_CXX:-$(command -v clang++ || command -v clang++-14 || true)}"
if [[ -z "$cxx" ]]; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev, as scripts/install_deps.sh does)" >&2
  exit 2
fi
mkdir -p "$build"
cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release > "$build/configure.log"
# Every harness: one build of the default target, so that the harnesses' own files compile in
# parallel (CMake's Makefiles build targets named on the command line one after the other).
if [[ $# -gt 0 ]]; then targets=(--target $(printf 'fuzz_%s ' "${harnesses[@]}")); else targets=(); fi
cmake --build "$build" -j"${SEMS_BUILD_JOBS:-2}" "${targets[@]}"

fuzz_one() { # harness: fuzzes, then prints its summary; exit 1 on a crash
  local h="$1"
  local corpus="$build/corpus/$h"      # grows while fuzzing; the seeds stay in fuzz/corpus
  mkdir -p "$corpus" "$build/artifacts/$h"
  local log="$build/fuzz_$h.log"
  local dict=()
  [[ "$h" != extractor ]] && dict=(-dict="$root/fuzz/json.dict") # the extractor's input is binary
  local rc=0
  nice "$build/fuzz_$h" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=4096 -max_len=8192 \
       "${dict[@]}" -artifact_prefix="$build/artifacts/$h/" -print_final_stats=1 \
       "$corpus" "$root/fuzz/corpus/$h" > "$log" 2>&1 || rc=1
  if [[ $rc -ne 0 ]]; then
    echo "fuzz.sh: fuzz_$h FOUND A CRASH:" >&2
    grep -E "ERROR|SUMMARY|Test unit written" "$log" >&2 || tail -20 "$log" >&2
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | sed "s/^/fuzz_$h: /" || true
  return $rc
}

jobs="${SEMS_FUZZ_JOBS:-$(nproc)}"
status=0
pids=()
for h in "${harnesses[@]}"; do
  echo "fuzz.sh: fuzz_$h for ${seconds} s (log $build/fuzz_$h.log)"
  fuzz_one "$h" & pids+=($!)
  if [[ ${#pids[@]} -ge $jobs ]]; then # a batch of `jobs` harnesses at a time
    for p in "${pids[@]}"; do wait "$p" || status=1; done
    pids=()
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
