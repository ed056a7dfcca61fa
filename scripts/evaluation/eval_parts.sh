# SPDX-License-Identifier: GPL-3.0-or-later
# Shared by the evaluation scripts (eval_full.sh, eval_kinematic.sh, eval_tracks.sh), sourced after they set
# `script` (their name), `out` (default DIR) and `log` (their record's file name): reads
# --out/--results/--size/--help, checks sems_eval, logs into RESULTS/$log, and defines
# `stamp` and `run_part NAME ARGS...` (one sems_eval process of one LibTorch thread with its
# own output folder and log under DIR).
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
results="$root/docs/results"
size=full
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --results) results="$2"; shift 2 ;;
    --size) size="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$root/scripts/evaluation/$script" | sed '$d'; exit 0 ;;
    *) echo "$script: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
eval_bin="${SEMS_EVAL:-$root/build/apps/sems_eval}"
[ -x "$eval_bin" ] || { echo "$script: $eval_bin is missing: build first (scripts/build.sh) or set SEMS_EVAL" >&2; exit 2; }
mkdir -p "$out" "$results"
# The run's own record (its stamps and the plotting output) goes beside the figures it made.
exec > >(tee "$results/$log") 2>&1
start=$(date +%s)
stamp() { echo "[$(date -u +%H:%M:%S)] $*"; }

run_part() { # name, then sems_eval arguments
  local name="$1"; shift
  local t0; t0=$(date +%s)
  if OMP_NUM_THREADS=1 "$eval_bin" --size "$size" --threads 1 --out "$out/$name" "$@" >"$out/$name.log" 2>&1; then
    stamp "$name done in $(( $(date +%s) - t0 )) s"
  else
    stamp "$name FAILED after $(( $(date +%s) - t0 )) s, see $out/$name.log"; return 1
  fi
}
