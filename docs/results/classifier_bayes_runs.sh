#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Bayes classifier runs of docs/RESULTS.md ("The best any decoder can do"), each with its
# log in docs/results/classifier_bayes/: the bound on the Doppler pattern next to experiment 1's
# networks (both scenes; writes bound_exp1_recognition.csv, which plot_results.py draws in the
# experiment-1 figure), the bound on other masks, the 30 000-frame re-check of the closest
# mask, the noiseless nearest-draw classifier, and where the spectral decoder's errors sit at
# 30 dB in the any scene, and the bound in the kinematic class library's scene (targets as
# bodies of scatterers; writes bound_kinematic.csv, with the classifiers of 30 000 and 300 000
# draws beside it). Needs the networks of scripts/evaluation/eval_full.sh
# in $EVAL_OUT (default out/eval_full) and a Release build (build/python_pkg). About 50 min
# of one core, and about 15 min of one core for the kinematic scene's runs.
#
#   bash docs/results/classifier_bayes_runs.sh [kinematic]
#
# With `kinematic`, only the kinematic scene's runs (they need no network of eval_full.sh; the
# 16-pilot masks are experiment 7's, copied into docs/results/masks_np16/ by eval_kinematic.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
nets="${EVAL_OUT:-out/eval_full}/full/bundles"  # the networks of scripts/evaluation/eval_full.sh --out DIR: EVAL_OUT=DIR
logs=docs/results/classifier_bayes
mkdir -p "$logs"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 PYTHONPATH=build/python_pkg
bayes() { /usr/bin/python3 docs/results/classifier_bayes.py "$@"; }
snrs=-10,-5,0,5,10,15,20,25,30
case "${1:-all}" in
  all|kinematic) ;;
  *) echo "classifier_bayes_runs.sh: unknown part \"$1\" (all or kinematic)" >&2; exit 2 ;;
esac
csv=docs/results/bound_exp1_recognition.csv
if [ "${1:-all}" = all ]; then
rm -f "$csv"
bayes --mask doppler --label doppler --heading approaching --bundle models/classifier \
  --bundle "$nets/cls_default_sems_s2026" --bundle "$nets/cls_default_sems_s2027" --bundle "$nets/cls_default_sems_s2028" \
  --bundle "$nets/cls_default_doppler_s2026" --bundle "$nets/cls_default_doppler_s2027" --bundle "$nets/cls_default_doppler_s2028" \
  --snr=$snrs --frames 30000 --prior 40000 --csv "$csv" > "$logs/default.log"
bayes --mask doppler --label doppler --heading any \
  --bundle "$nets/cls_any_sems_s2026" --bundle "$nets/cls_any_sems_s2027" --bundle "$nets/cls_any_sems_s2028" \
  --bundle "$nets/cls_any_doppler_s2026" --bundle "$nets/cls_any_doppler_s2027" --bundle "$nets/cls_any_doppler_s2028" \
  --snr=$snrs --frames 30000 --prior 40000 --csv "$csv" > "$logs/any.log"
for h in approaching any; do
  bayes --mask doppler --mask blocks:2,16 --mask blocks:2,16,2 --mask blocks:4,8 --mask blocks:4,8,4 --mask blocks:2,16,1,2 \
    --heading $h --snr=-5,0,5,10 --frames 10000 --prior 40000 > "$logs/masks_$h.log"
done
mkdir -p out/blocks
[ -d out/blocks/default_b2x16_s2026 ] || {
  bayes --mask blocks:2,16 --save-mask out/blocks/blocks_2_16.json > /dev/null
  build/apps/sems_train --task classify --snr-min -10 --snr-max 30 --frames 30000 --batch 256 --threads 1 --seed 2026 \
    --eval-snr=-10,-5,0,5,10,15,20,25,30 --heading approaching --mask out/blocks/blocks_2_16.json --epochs 9 \
    --out out/blocks/default_b2x16_s2026 > "$logs/train_blocks_2_16_s2026.log"
}
bayes --mask doppler --mask blocks:2,16 --heading approaching --bundle "$nets/cls_default_doppler_s2026" \
  --bundle out/blocks/default_b2x16_s2026 --snr 5,10 --frames 30000 --prior 40000 > "$logs/recheck_blocks_2_16.log"
for h in approaching any; do
  bayes --mask doppler --label doppler --heading $h --snr inf --frames 30000 --prior 40000 > "$logs/noiseless_$h.log"
done
# where the spectral decoder loses to the bound at high SNR in the any scene
/usr/bin/python3 docs/results/classifier_errors_by_fade.py --bundle "$nets/cls_any_sems_s2026" --snr 30 --frames 10000 \
  --heading any > "$logs/errors_any_30dB.log"
fi
# the kinematic library's scene (any heading): the Doppler pattern with 32 and with 128 pilots
kcsv=docs/results/bound_kinematic.csv
rm -f "$kcsv"
bayes --scene models/scenes/kinematic_any.json --mask doppler --label doppler --snr=$snrs --frames 3000 \
  --prior 120000 --csv "$kcsv" > "$logs/kinematic_doppler.log"
bayes --scene models/scenes/kinematic_any.json --mask doppler:128 --label doppler_128 --snr=$snrs --frames 3000 \
  --prior 20000 --csv "$kcsv" > "$logs/kinematic_doppler_128.log"
# the same classifier as a decoder that knows only 30 000 draws (5 000 per class: as many frames as a
# network's whole budget in experiment 7, 24 000 of them for training) and 300 000: how much of the gap to the bound is the
# number of draws (rows "Bayes classifier from N prior draws (a decoder)")
for per_class in 5000 50000; do
  bayes --scene models/scenes/kinematic_any.json --mask doppler --label doppler --snr=$snrs --frames 3000 \
    --prior $per_class --as-decoder --csv "$kcsv" > "$logs/kinematic_doppler_draws_$((6 * per_class)).log"
done
# the 16-pilot masks experiment 7's learner chose (the bank part's three seeds) against the Doppler
# pattern of 16 pilots, where the network alone on them trails it
bayes --scene models/scenes/kinematic_any.json --mask doppler:16 --label doppler_16 \
  --mask docs/results/masks_np16/learned_s2026.json --label learned_s2026 \
  --mask docs/results/masks_np16/learned_s2027.json --label learned_s2027 \
  --mask docs/results/masks_np16/learned_s2028.json --label learned_s2028 \
  --snr=-10,-5,0 --frames 3000 --prior 40000 > "$logs/kinematic_masks_np16.log"
# the template bank's likelihood against the exact one without the SNR and the one given it, on
# 24 000 draws (experiment 7's training frames) and no network: is the gap the likelihood?
/usr/bin/python3 docs/results/bank_likelihoods.py --scene models/scenes/kinematic_any.json --templates 24000 \
  --frames 3000 > "$logs/bank_likelihoods.log"
echo "classifier_bayes_runs: logs in $logs, bound rows in $([ "${1:-all}" = all ] && echo "$csv and ")$kcsv"
