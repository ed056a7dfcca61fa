#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# A bundle trains again from its own bundle.json: `sems_train --from BUNDLE` with today's
# binary gives the same mask and weights, bit for bit, for the same seed. Tiny bundles (a
# learned-mask classifier, a delay decoder on a seeded mask pattern) are trained, then trained
# again with --from; the shipped bundles' records must be complete (--dry-run resolves them).
#
#   check_train_from.sh SEMS_TRAIN SOURCE_DIR WORK_DIR
set -euo pipefail
train="$1" src="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
fail() { echo "check_train_from: $*" >&2; exit 1; }
same() { # same A B FILE: byte-identical
  cmp "$1/$3" "$2/$3" || fail "$2/$3 differs from $1/$3"
}

"$train" --task classify --frames 300 --epochs 2 --decoder-epochs 1 --batch 64 --threads 1 --seed 7 \
  --width 4 --hidden 16 --snr-min 0 --snr-max 20 --eval-snr 10 --quiet --out "$work/classify" > /dev/null
grep -q '"measured_by": "sems_train test split"' "$work/classify/model_card.json" \
  || fail "sems_train wrote no model card with its test split in $work/classify"
"$train" --from "$work/classify" --out "$work/classify_again" --quiet > /dev/null
same "$work/classify" "$work/classify_again" decoder.pt
same "$work/classify" "$work/classify_again" mask.json

"$train" --task delay --mask-pattern random --frames 200 --epochs 1 --batch 64 --threads 1 --seed 3 \
  --width 4 --depth 3 --delay-spacing 0.5 --snr 20 --eval-snr 20 --pilot-phases newman --quiet \
  --out "$work/delay" > /dev/null
"$train" --from "$work/delay" --out "$work/delay_again" --quiet > /dev/null
same "$work/delay" "$work/delay_again" decoder.pt
same "$work/delay" "$work/delay_again" mask.json
grep -q '"phases": "newman"' "$work/delay_again/mask.json" || fail "--pilot-phases newman is not in $work/delay_again/mask.json"

# A size override is taken, the rest is the bundle's; other settings are refused.
"$train" --from "$work/classify" --frames 200 --out "$work/smaller" --quiet > /dev/null
/usr/bin/python3 - "$work" <<'PY'
import json, sys
a = json.load(open(sys.argv[1] + "/classify/bundle.json"))["training"]
b = json.load(open(sys.argv[1] + "/smaller/bundle.json"))["training"]
assert b["frames"] == 200 and a["frames"] == 300, (a["frames"], b["frames"])
for k in ("seed", "epochs", "decoder_epochs", "batch", "lr", "mask_settle_epochs", "scene", "encoder"):
    assert a[k] == b[k], k
PY
if "$train" --from "$work/classify" --seed 2 --out "$work/refused" --quiet 2> "$work/refused.log"; then
  fail "--seed with --from was accepted"
fi
grep -q -- "--seed cannot be given with --from" "$work/refused.log" || { cat "$work/refused.log"; fail "unclear refusal"; }

# Every shipped bundle's record is complete: its settings resolve (no training).
for b in "$src"/models/*/bundle.json; do
  dir="$(dirname "$b")"
  "$train" --from "$dir" --out "$work/unused" --dry-run > "$work/dry.json" \
    || fail "$dir: its recorded settings do not resolve"
done
echo "check_train_from: retrained bundles are bit-identical; every shipped bundle's settings resolve"
