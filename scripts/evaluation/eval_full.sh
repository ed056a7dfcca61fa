#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The documented full evaluation (docs/RESULTS.md): all six experiments of `sems_eval --size
# full` at the paper's budget, split over three processes of one LibTorch thread each so both
# cores stay busy, then the shipped bundles' rows, one set of CSVs and the figures.
#
#   bash scripts/evaluation/eval_full.sh [--out DIR] [--results DIR] [--size full|test] [--test-frames N]
#
# Processes (each its own output folder under DIR, default out/eval_full), balanced so that
# they end together (the N_p sweep of experiment 5 is split over all three):
#   full   experiments 1, 2 (t-SNE of experiment 1's networks, from the same cache), 5 at
#          N_p 2 and 8, 6
#   full4  experiment 4 single path, then 5 at N_p 16, then experiment 3 (without micro-Doppler; strong clutter), 6
#   full4b experiment 4 multipath, then experiment 5 at N_p 32 (experiment 4's network from the
#          same cache), 64 and 128, 6
# then `--only-shipped` for models/, docs/results/combine_runs.py and apps/figures/plot_results.py into
# RESULTS (default docs/results), with the per-frame predictions of experiments 1, 3, 4 and 5 merged
# over the parts (<csv stem>_predictions.npz, exp<N>_truth.npz; apps/figures/predictions.py), every
# CSV score checked against them, and the paired tests of the claims (apps/figures/claims.py,
# RESULTS/claims.md, with experiment 7's, in claims_kinematic.md, when its predictions are there). --test-frames N sets the
# test frames per operating point of every part (the full size's 3000 otherwise; e.g. 30000).
# Prints the wall time of each part and of the whole run, also into RESULTS/eval_full.log.
# The programs are $SEMS_EVAL (default build/apps/sems_eval) and /usr/bin/python3. --size test
# runs the same plumbing in a minute (numbers meaningless).
set -euo pipefail
script=eval_full.sh
takes_test_frames=1
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_full"
log=eval_full.log
source "$(dirname "$0")/eval_parts.sh"

stamp "sems_eval --size $size, 3 processes, logs in $out/*.log"
pids=()
# The parts' N_p lists together are --size full's sweep (config::np_sweep in apps/evaluation/sems_eval.cc,
# 2..128), split by cost; --size test: N_p 2, 8 and 32, one per part.
if [ "$size" = full ]; then np_full=(--np-sweep 2,8); np_full4=(--np-sweep 16); np_full4b=(--np-sweep 32,64,128)
else np_full=(--np-sweep 2); np_full4=(--np-sweep 8); np_full4b=(--np-sweep 32); fi
run_part full --experiments 1,2,5,6 "${np_full[@]}" & pids+=($!)
run_part full4 --experiments 3,4,5,6 --delay-scenarios single "${np_full4[@]}" & pids+=($!)
run_part full4b --experiments 4,5,6 --delay-scenarios multipath "${np_full4b[@]}" & pids+=($!)
failed=0
for p in "${pids[@]}"; do wait "$p" || failed=1; done
[ "$failed" -eq 0 ] || { stamp "a part failed"; exit 1; }
run_part shipped --experiments 1,4 --only-shipped --shipped-classifier "$root/models/classifier" \
  --shipped-delay-single "$root/models/delay_single" --shipped-delay-multipath "$root/models/delay_multipath"
/usr/bin/python3 "$root/docs/results/combine_runs.py" "$out" "$results"
# The kept predictions, as combine_runs.py merges the CSVs: experiment 1 from full, 3 from full4,
# 4 from full4 (single path) and full4b (multipath), 5 from all three; the shipped rows beside.
kept exp1_recognition_predictions.npz full
kept exp1_truth.npz full
kept exp3_conditions_predictions.npz full4
kept exp3_truth.npz full4
kept exp4_delay_predictions.npz full4 full4b
kept exp4_truth.npz full4 full4b
kept exp5_pilot_budget_predictions.npz full full4 full4b
kept exp5_truth.npz full full4 full4b
for f in exp1_recognition exp4_delay; do
  if [ -f "$out/shipped/${f}_predictions.npz" ]; then
    /usr/bin/python3 "$root/apps/figures/predictions.py" merge "$results/shipped_${f}_predictions.npz" \
      "$out/shipped/${f}_predictions.npz"
  fi
done
/usr/bin/python3 "$root/apps/figures/predictions.py" check "$results" 1,3,4,5
/usr/bin/python3 "$root/apps/figures/plot_results.py" "$results" --tables "$results/tables.md"
/usr/bin/python3 "$root/apps/figures/claims.py" "$results"
for f in "$out"/*.log; do cp "$f" "$results/eval_full_$(basename "$f")"; done
stamp "whole run: $(( ($(date +%s) - start) / 60 )) min $(( ($(date +%s) - start) % 60 )) s"
