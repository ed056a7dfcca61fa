#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Experiment 9 of docs/RESULTS.md: an array's pilots, in five processes of one LibTorch thread
# each, then their figures and tables.
#
#   bash scripts/evaluation/eval_arrays.sh [--out DIR] [--results DIR] [--size full|test]
#
# Processes (each its own folder and log under DIR, default out/eval_arrays):
#   angle     azimuth estimates against SNR next to the CRB, one and two targets: beamforming,
#             Capon, MUSIC and the position bundles in SEMS_EXP9_POSITION_BUNDLES (comma-separated,
#             one per training seed, of one mask and array; default the shipped
#             models/position_ula8, seed 1) on their mask and 8-element array
#   classes   classification per frame with 1, 4 and 8 elements, each frame beamformed as SemS
#             Classifier Sink does, by the classifier bundles in SEMS_EXP9_CLASSIFIERS
#             (comma-separated, one per training seed; default the shipped
#             models/classifier_kinematic, trained with seed 2026)
#   tracks    the shipped track bundle (models/classifier_kinematic_track) deciding over tracks
#             that cross the line of sight, with the same arrays
#   mimo      MIMO masks for the mimo2x4_3g array: learned (three seeds) against same pilots,
#             time and frequency division, by the azimuth's bound and its maximum-likelihood
#             estimate on the same frames (about 40 minutes: the longest part)
#   mimo_budget  the same masks' bounds at 4, 8 and 16 pilots (about 25 minutes)
# The results (exp9_angle.csv and .md and .png with exp9_angle_predictions.npz;
# exp9_classes.csv and .md and .png with exp9_classes_predictions.npz and exp9_truth.npz;
# exp9_tracks.csv with exp9_tracks_predictions.csv and exp9_tracks_truth.csv; exp9_mimo.csv,
# exp9_mimo_masks.csv, exp9_mimo_budget.csv and .md and .png with exp9_mimo_predictions.npz, the
# masks in masks_mimo/) go to
# RESULTS (default docs/results), the run's record to RESULTS/eval_arrays.log and the parts'
# logs to RESULTS/eval_arrays_<part>.log. --size test runs the same plumbing in a minute.
set -euo pipefail
script=eval_arrays.sh
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_arrays"
log=eval_arrays.log
source "$(dirname "$0")/eval_parts.sh"
# Folders as the logs name them: relative to the working directory (run from the source tree,
# the logs name no folder of the machine).
here() { realpath -m --relative-to=. "$1"; }
out="$(here "$out")"
results="$(here "$results")"
classifiers="${SEMS_EXP9_CLASSIFIERS:-$(here "$root/models/classifier_kinematic")}"
positions="${SEMS_EXP9_POSITION_BUNDLES:-$(here "$root/models/position_ula8")}"

stamp "sems_eval --size $size --experiments 9, 5 processes, logs in $out/*.log"
pids=()
run_part angle --experiments 9 --exp9-parts angle --exp9-position-bundle "$positions" & pids+=($!)
run_part classes --experiments 9 --exp9-parts classes --exp9-classifier-bundles "$classifiers" & pids+=($!)
run_part tracks --experiments 9 --exp9-parts tracks --exp9-track-bundle "$(here "$root/models/classifier_kinematic_track")" & pids+=($!)
run_part mimo --experiments 9 --exp9-parts mimo & pids+=($!)
run_part mimo_budget --experiments 9 --exp9-parts mimo_budget & pids+=($!)
status=0
for p in "${pids[@]}"; do wait "$p" || status=1; done
[ "$status" = 0 ] || { stamp "a part failed"; exit 1; }
cp "$out/angle/exp9_angle.csv" "$out/angle/exp9_angle_predictions.csv" "$results/"
cp "$out/classes/exp9_classes.csv" "$out/classes/exp9_classes_predictions.npz" "$out/classes/exp9_truth.npz" "$results/"
cp "$out/tracks/exp9_tracks.csv" "$out/tracks/exp9_tracks_predictions.csv" "$out/tracks/exp9_tracks_truth.csv" "$results/"
cp "$out/mimo/exp9_mimo.csv" "$out/mimo/exp9_mimo_masks.csv" "$out/mimo/exp9_mimo_predictions.csv" \
   "$out/mimo_budget/exp9_mimo_budget.csv" "$results/"
rm -rf "$results/masks_mimo" && cp -r "$out/mimo/masks_mimo" "$results/"
for p in angle classes tracks mimo mimo_budget; do cp "$out/$p.log" "$results/eval_arrays_$p.log"; done
/usr/bin/python3 "$root/apps/figures/predictions.py" check "$results" 9
/usr/bin/python3 "$root/apps/figures/plot_angle.py" "$results"
rm -f "$results/exp9_angle_predictions.csv" # packed into exp9_angle_predictions.npz by plot_angle.py
/usr/bin/python3 "$root/apps/figures/plot_array_classes.py" "$results"
/usr/bin/python3 "$root/apps/figures/plot_mimo.py" "$results"
rm -f "$results/exp9_mimo_predictions.csv" # packed into exp9_mimo_predictions.npz by plot_mimo.py
stamp "done in $(( $(date +%s) - start )) s"
