#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Experiment 8's second scene (docs/RESULTS.md): decisions over a track on the NR-like frame
# nr_sensing_120khz, whose 0.125 ms symbol interval samples the kinematic library's rotors
# without folding. SemS-track against the Doppler and staggered patterns under the same
# temporal decoder and the fusion of each, at 32 pilots, training seed 2026, on 300 test
# tracks of 64 frames of 4 ms (0.26 s).
#
#   bash scripts/evaluation/eval_tracks_nr.sh [--out DIR] [--results DIR] [--size full|test]
#
# One sems_eval process of one LibTorch thread (its folder and log under DIR, default
# out/eval_tracks_nr); trained networks are cached there. The CSVs, exp8_*.png and
# track_tables.md go to RESULTS (default docs/results/exp8_nr), the run's record to
# RESULTS/eval_tracks_nr.log.
set -euo pipefail
script=eval_tracks_nr.sh
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_tracks_nr"
log=eval_tracks_nr.log
root="$(cd "$(dirname "$0")/../.." && pwd)"
args=("$@")
[[ " ${args[*]} " == *" --results "* ]] || args+=(--results "$root/docs/results/exp8_nr")
set -- "${args[@]}"
source "$(dirname "$0")/eval_parts.sh"

stamp "sems_eval --size $size --experiments 8 on nr_sensing_120khz, log in $out/nr_s0.log"
status=0
run_part nr_s0 --frame nr_sensing_120khz --experiments 8 --seeds 1 --exp8-parts budget --exp8-np-sweep 32 \
  --first-seed 0 || status=1
for kind in tracks predictions truth; do
  [ -f "$out/nr_s0/exp8_$kind.csv" ] && cp "$out/nr_s0/exp8_$kind.csv" "$results/exp8_$kind.csv"
done
cp "$out/nr_s0.log" "$results/eval_tracks_nr_s0.log"
/usr/bin/python3 "$root/apps/figures/plot_tracks.py" "$results" --tables "$results/track_tables.md" --frame-ms 4 \
  --script scripts/evaluation/eval_tracks_nr.sh
stamp "done in $(( $(date +%s) - start )) s"
exit "$status"
