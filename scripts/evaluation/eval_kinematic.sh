#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Experiment 7 of docs/RESULTS.md: semantic sensing on targets of moving scatterers (the
# kinematic class library, any heading), at the paper's budget, split over three processes of one
# LibTorch thread each (two more, short, beside them), then its CSVs, figures and tables.
#
#   bash scripts/evaluation/eval_kinematic.sh [--out DIR] [--results DIR] [--size full|test] [--test-frames N]
#
# Processes (each its own output folder under DIR, default out/eval_kinematic):
#   main    N_p = 32: SemS, SemS + template bank, the SemS decoder on the Doppler, uniform,
#           random and staggered patterns, MSE-DL, Perfect CSI (noiseless and at the test SNR), the feature SVMs;
#           confusion matrices at 10 dB
#   budget  SemS against the Doppler and staggered patterns at N_p = 128, 64, 16, 8
#   power   SemS whose mask learner also shares the pilots' total energy, at N_p = 32 and 128
#   bank    SemS and the Doppler pattern's decoder, each with a template bank, at N_p = 16 and 64
#   burst   the SemS decoder on the burst pattern at N_p = 8 and 16 (beside the budget part's patterns)
# Trained networks are cached in DIR/<part>/bundles: a re-run with the same settings only
# re-evaluates, and a stopped run resumes. The results (exp7_*.csv, the per-frame predictions
# exp7_*_predictions.npz and exp7_truth.npz, the learned masks in masks_exp7/, exp7_*.png,
# kinematic_tables.md with its paired tests, and claims.md and claims_kinematic.md with experiments 1-5's where their predictions are there) go to RESULTS (default
# docs/results), the run's record to
# RESULTS/eval_kinematic.log and the parts' logs to RESULTS/eval_kinematic_<part>.log. The programs are $SEMS_EVAL (default build/apps/sems_eval) and
# /usr/bin/python3. --size test runs the same plumbing in a minute (numbers meaningless).
# --test-frames N sets the test frames per operating point of every part (the full size's 3000
# otherwise; e.g. 30000 for tighter paired tests).
set -euo pipefail
script=eval_kinematic.sh
takes_test_frames=1
out="$(cd "$(dirname "$0")/../.." && pwd)/out/eval_kinematic"
log=eval_kinematic.log
source "$(dirname "$0")/eval_parts.sh"

stamp "sems_eval --size $size --experiments 7, 5 processes, logs in $out/*.log"
pids=()
run_part main --experiments 7 --exp7-parts main & pids+=($!)
run_part budget --experiments 7 --exp7-parts budget & pids+=($!)
run_part power --experiments 7 --exp7-parts power & pids+=($!)
run_part bank --experiments 7 --exp7-parts bank & pids+=($!)
run_part burst --experiments 7 --exp7-parts burst & pids+=($!)
status=0
for p in "${pids[@]}"; do wait "$p" || status=1; done
[ "$status" = 0 ] || { stamp "a part failed"; exit 1; }
cp "$out/main/exp7_kinematic.csv" "$out/main/exp7_confusion.csv" "$out/budget/exp7_pilot_budget.csv" \
   "$out/power/exp7_pilot_power.csv" "$out/bank/exp7_bank.csv" "$out/burst/exp7_burst.csv" "$results/"
for p in main budget power bank burst; do cp "$out/$p.log" "$results/eval_kinematic_$p.log"; done
# Each part's predictions beside its CSV; the truth is the same test frames in every part.
kept exp7_kinematic_predictions.npz main
kept exp7_pilot_budget_predictions.npz budget
kept exp7_pilot_power_predictions.npz power
kept exp7_bank_predictions.npz bank
kept exp7_burst_predictions.npz burst
kept exp7_truth.npz main budget power bank burst
# Every learned mask behind a row (each part's SemS and MSE-DL learners, each seed), and the bank
# part's 16-pilot ones again where docs/results/classifier_bayes_runs.sh reads them.
mkdir -p "$results/masks_exp7" "$results/masks_np16"
for p in main budget power bank; do
  for b in "$out/$p"/bundles/*_sems*_s* "$out/$p"/bundles/*_mse_s*; do
    [ -f "$b/mask.json" ] && cp "$b/mask.json" "$results/masks_exp7/$(basename "$b").json"
  done
done
for s in 2026 2027 2028; do  # the seeds the full size trains (--size test trains fewer)
  m="$out/bank/bundles/cls_kinematic_np16_sems_templates_s$s/mask.json"
  [ -f "$m" ] && cp "$m" "$results/masks_np16/learned_s$s.json"
done
/usr/bin/python3 "$root/apps/figures/predictions.py" check "$results" 7
/usr/bin/python3 "$root/apps/figures/plot_kinematic.py" "$results" --tables "$results/kinematic_tables.md"
/usr/bin/python3 "$root/apps/figures/claims.py" "$results"
stamp "done in $(( $(date +%s) - start )) s"
