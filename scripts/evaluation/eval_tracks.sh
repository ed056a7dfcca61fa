#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Experiment 8 of docs/RESULTS.md: decisions over a track (the kinematic library, any heading,
# tracks of 64 frames), every method on the same 300 test tracks, then its figures, tables and
# paired statistics.
#
#   bash scripts/evaluation/eval_tracks.sh [--out DIR] [--results DIR] [--size full|test]
#
# Processes (one LibTorch thread each, two at a time; each its own folder and log under DIR,
# default out/eval_tracks):
#   main_s0, main_s1, main_s2   N_p = 32, every method, training seed 2026, 2027, 2028
#   budget8_s0                  SemS-track against the hand patterns under the temporal decoder
#                               at N_p = 8, training seed 2026
#   budget128_s0                the same at N_p = 128
#   shipped                     the shipped track bundle (models/classifier_kinematic_track) and
#                               its frame decoder's fusion on the same tracks (no training)
#   superframe8_s0, superframe32_s0
#                               learned super-frame masks of 4 sets from the SemS frame bundle
#                               at N_p = 8 and 32 under the temporal decoder, and the SemS decoder
#                               on its mask moved across the band frame by frame (training seed 2026)
#   superframe8r_s0             the same at N_p = 8 with the sets started at random
# Trained networks are cached in DIR/<part>/bundles: a re-run with the same settings only
# re-evaluates, and a stopped run resumes. SEMS_EVAL_PARTS (space-separated) runs a subset;
# the parts whose CSVs exist are merged. The results (exp8_*.csv, exp8_*.png and
# track_tables.md, track_pilots.md) go to RESULTS (default docs/results), the run's record to
# RESULTS/eval_tracks.log. --size test runs the same plumbing in a minute (numbers meaningless).
set -euo pipefail
script=eval_tracks.sh
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_tracks"
log=eval_tracks.log
source "$(dirname "$0")/eval_parts.sh"

declare -A part_args=(
  [main_s0]="--exp8-parts main --first-seed 0"
  [main_s1]="--exp8-parts main --first-seed 1"
  [main_s2]="--exp8-parts main --first-seed 2"
  [budget8_s0]="--exp8-parts budget --exp8-np-sweep 8 --first-seed 0"
  [budget128_s0]="--exp8-parts budget --exp8-np-sweep 128 --first-seed 0"
  [shipped]="--exp8-parts main --only-shipped --shipped-track $root/models/classifier_kinematic_track"
  [superframe8_s0]="--exp8-parts superframe --exp8-np-sweep 8 --first-seed 0"
  [superframe32_s0]="--exp8-parts superframe --exp8-np-sweep 32 --first-seed 0"
  [superframe8r_s0]="--exp8-parts superframe --exp8-np-sweep 8 --exp8-super-frame-start random --first-seed 0"
)
parts=(${SEMS_EVAL_PARTS:-main_s0 main_s1 budget8_s0 main_s2 budget128_s0 shipped superframe8_s0 superframe32_s0
  superframe8r_s0})
stamp "sems_eval --size $size --experiments 8, parts ${parts[*]}, two at a time, logs in $out/*.log"
status=0
running=()
for p in "${parts[@]}"; do
  [ -n "${part_args[$p]:-}" ] || { stamp "unknown part $p (one of ${!part_args[*]})"; exit 2; }
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do wait -n || status=1; done
  # shellcheck disable=SC2086
  run_part "$p" --experiments 8 --seeds 1 ${part_args[$p]} &
done
while [ "$(jobs -rp | wc -l)" -gt 0 ]; do wait -n || status=1; done
[ "$status" = 0 ] || stamp "a part failed: merging the parts that finished"
# One CSV of each kind over the parts that wrote one (header once); the truth is the same in all.
merged=0
for kind in tracks predictions truth; do
  first=1
  for p in "${!part_args[@]}"; do
    f="$out/$p/exp8_$kind.csv"
    [ -f "$f" ] || continue
    if [ "$first" = 1 ]; then cp "$f" "$results/exp8_$kind.csv"; first=0; merged=1
    elif [ "$kind" != truth ]; then tail -n +2 "$f" >> "$results/exp8_$kind.csv"; fi
  done
done
[ "$merged" = 1 ] || { stamp "no part wrote exp8_tracks.csv"; exit 1; }
for p in "${!part_args[@]}"; do [ -f "$out/$p.log" ] && cp "$out/$p.log" "$results/eval_tracks_$p.log"; done
/usr/bin/python3 "$root/apps/figures/plot_tracks.py" "$results" --tables "$results/track_tables.md"
stamp "done in $(( $(date +%s) - start )) s"
exit "$status"
