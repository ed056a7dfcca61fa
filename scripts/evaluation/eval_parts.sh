# SPDX-License-Identifier: GPL-3.0-or-later
# Shared by the evaluation scripts (eval_full.sh, eval_kinematic.sh, eval_tracks.sh, eval_tracks_nr.sh,
# eval_arrays.sh), sourced after they set
# `script` (their name), `out` (default DIR) and `log` (their record's file name): reads
# --out/--results/--size/--help (and --test-frames N where the script sets takes_test_frames=1:
# test frames per operating point, passed to every part), checks sems_eval, logs into
# RESULTS/$log, and defines `stamp`, `run_part NAME ARGS...` (one sems_eval process of one
# LibTorch thread with its own output folder and log under DIR) and `kept FILE PART...` (a
# kept-predictions or truth file of the parts' folders merged into RESULTS).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
results="$root/docs/results"
size=full
test_frames=()
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --results) results="$2"; shift 2 ;;
    --size) size="$2"; shift 2 ;;
    --test-frames)
      [ "${takes_test_frames:-0}" = 1 ] || { echo "$script: unknown option $1 (see --help)" >&2; exit 2; }
      [[ "${2:-}" =~ ^[0-9]+$ ]] || { echo "$script: --test-frames needs a whole number of frames, got \"${2:-}\"" >&2; exit 2; }
      test_frames=(--test-frames "$2"); shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$root/scripts/evaluation/$script" | sed '$d'; exit 0 ;;
    *) echo "$script: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
eval_bin="${SEMS_EVAL:-$root/build/apps/sems_eval}"
[ -x "$eval_bin" ] || { echo "$script: $eval_bin is missing: build the apps first (SEMS_BUILD_APPS=ON bash scripts/build.sh) or set SEMS_EVAL" >&2; exit 2; }
mkdir -p "$out" "$results"
# The run's own record (its stamps and the plotting output) goes beside the figures it made.
exec > >(tee "$results/$log") 2>&1
start=$(date +%s)
stamp() { echo "[$(date -u +%H:%M:%S)] $*"; }

run_part() { # name, then sems_eval arguments
  local name="$1"; shift
  local t0; t0=$(date +%s)
  if OMP_NUM_THREADS=1 "$eval_bin" --size "$size" "${test_frames[@]}" --threads 1 --out "$out/$name" "$@" \
      >"$out/$name.log" 2>&1; then
    stamp "$name done in $(( $(date +%s) - t0 )) s"
  else
    stamp "$name FAILED after $(( $(date +%s) - t0 )) s, see $out/$name.log"; return 1
  fi
}

kept() { # file name, then the parts whose folders hold it: merged (or copied) into RESULTS
  local name="$1"; shift
  local files=() p
  for p in "$@"; do [ -f "$out/$p/$name" ] && files+=("$out/$p/$name"); done
  [ "${#files[@]}" -gt 0 ] || { stamp "no part wrote $name"; return 1; }
  /usr/bin/python3 "$root/apps/figures/predictions.py" merge "$results/$name" "${files[@]}"
}
