#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Adults against children over a track with the module's own decoders, and what 4 and 8
# receive elements add (docs/results/arrays.md, "Adults against children over a track").
#
#   bash scripts/evaluation/eval_adult_child.sh [--out DIR] [--results DIR] [--size full|test]
#
# Three track bundles of kind acf_tcn (training seeds 2026, 2027, 2028) over the shipped frame
# bundle models/classifier_kinematic, trained on the pair's scene models/scenes/adult_child_tracks.json
# (8 000 tracks of up to 64 frames at 20 to 30 dB per pilot, one antenna: the sink's beamformer makes
# an array's pilots one antenna's), two at a time, one LibTorch thread each; then experiment 9's
# tracks part of sems_eval on each (1 000 straight tracks of up to 64 frames, the same for every
# bundle, ULAs of 1, 4 and 8 elements, 10, 20 and 30 dB per pilot and element), then
# apps/figures/pair_tracks.py: RESULTS/adult_child_track.md (default RESULTS docs/results). The
# bundles and runs go to DIR (default out/eval_adult_child), the runs' CSVs to
# RESULTS/adult_child_track/s<seed>/, the record to RESULTS/eval_adult_child.log and the
# trainings' and runs' logs beside the CSVs. The programs are $SEMS_TRAIN and $SEMS_EVAL (default
# build/apps/sems_train and build/apps/sems_eval) and /usr/bin/python3. About an hour on 2 cores.
# --size test runs the same plumbing in a minute or two (numbers meaningless).
set -euo pipefail
script=eval_adult_child.sh
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_adult_child"
log=eval_adult_child.log
source "$(dirname "$0")/eval_parts.sh"
train_bin="${SEMS_TRAIN:-$root/build/apps/sems_train}"
[ -x "$train_bin" ] || { echo "$script: $train_bin is missing: build the apps first (SEMS_BUILD_APPS=ON bash scripts/build.sh) or set SEMS_TRAIN" >&2; exit 2; }
if [ "$size" = test ]; then
  train=(--tracks 60 --epochs 1 --track-frames 8); count=12; frames=8
else
  train=(--tracks 8000 --epochs 40 --patience 8 --track-frames 64); count=1000; frames=64
fi
seeds=(2026 2027 2028)

train_one() { # seed
  local s="$1" t0; t0=$(date +%s)
  if OMP_NUM_THREADS=1 "$train_bin" --frame-bundle "$root/models/classifier_kinematic" \
      --scene "$root/models/scenes/adult_child_tracks.json" "${train[@]}" --snr-min 20 --snr-max 30 --threads 1 \
      --seed "$s" --eval-snr 20,30 --track-model acf_tcn --out "$out/bundle_s$s" > "$out/train_s$s.log" 2>&1; then
    stamp "bundle seed $s trained in $(( $(date +%s) - t0 )) s"
  else
    stamp "bundle seed $s FAILED, see $out/train_s$s.log"; return 1
  fi
}

stamp "3 track bundles (acf_tcn) of the adult/child pair, two at a time, logs in ${out#"$root"/}/train_s*.log"
# Every background job is waited for, failed or not, before the script ends: none is left
# writing into DIR after a failure.
status=0
train_one "${seeds[0]}" & a=$!
train_one "${seeds[1]}" & b=$!
wait "$a" || status=1
wait "$b" || status=1
[ "$status" = 0 ] || { stamp "a training failed"; exit 1; }
train_one "${seeds[2]}" & a=$!
for s in "${seeds[0]}" "${seeds[1]}"; do
  run_part "tracks_s$s" --experiments 9 --exp9-parts tracks --exp9-track-bundle "$out/bundle_s$s" \
    --exp9-track-count "$count" --exp9-track-frames "$frames" --snrs 10,20,30 || { status=1; break; }
done
wait "$a" || status=1
[ "$status" = 0 ] || { stamp "a part failed"; exit 1; }
run_part "tracks_s${seeds[2]}" --experiments 9 --exp9-parts tracks --exp9-track-bundle "$out/bundle_s${seeds[2]}" \
  --exp9-track-count "$count" --exp9-track-frames "$frames" --snrs 10,20,30
runs=()
for s in "${seeds[@]}"; do
  d="$results/adult_child_track/s$s"
  mkdir -p "$d"
  cp "$out/tracks_s$s/exp9_tracks.csv" "$out/tracks_s$s/exp9_tracks_predictions.csv" \
     "$out/tracks_s$s/exp9_tracks_truth.csv" "$d/"
  sed "s#$out#out/eval_adult_child#g" "$out/train_s$s.log" > "$d/train.log"
  sed "s#$out#out/eval_adult_child#g" "$out/tracks_s$s.log" > "$d/tracks.log"
  runs+=("$d")
done
/usr/bin/python3 "$root/apps/figures/pair_tracks.py" "${runs[@]}" --out "$results/adult_child_track.md" \
  --command "bash scripts/evaluation/eval_adult_child.sh" | sed "s#$root/##"
stamp "done in $(( $(date +%s) - start )) s"
