#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Learned pilots against the hand-made Doppler pattern, same decoder, same budget.

For each scene (default / any heading) and training seed, sems_train trains
  - SemS: the mask learned from a cold start (6 mask + 3 decoder epochs), and
  - the Doppler pattern (one subcarrier x N_p symbols), decoder only (9 epochs),
with the same seed, hence the same training, validation and test frames (the paper's
budget: 30 000 frames 8:1:1, batch 256, 3 000 test frames per SNR point). Each
bundle's test metrics are read back; the table gives the mean over seeds and the
difference learned - Doppler with two standard errors (binomial, per seed, combined).

  /usr/bin/python3 docs/results/learned_vs_hand.py run --train build/apps/sems_train --out OUT
  /usr/bin/python3 docs/results/learned_vs_hand.py table --out OUT > table.md

The decoder is the range-gated spectral decoder as it was before the chirp fit and the leaky
ReLU: `run` passes --chirp-bins 0 and --conv-slope 0 (today's sems_train defaults are 9 and
0.1), so that it trains what the page's tables show. The page's last table, the any scene's
seed 2026 with the leaky ReLU, is
  learned_vs_hand.py run --out OUT_FIX --scenes any --seeds 2026 --conv-slope 0.1
  learned_vs_hand.py table --out OUT_FIX --scenes any --seeds 2026
"""
import argparse
import json
import math
import os
import subprocess
import sys

SNRS = "-10,-5,0,5,10,15,20,25,30"
SCENES = {"default": ["--heading", "approaching"], "any": ["--heading", "any"]}
METHODS = {
    "learned": ["--epochs", "6", "--decoder-epochs", "3"],
    "doppler": ["--mask-pattern", "doppler", "--epochs", "9"],
}


def name(scene, method, seed):
    return "%s_%s_s%d" % (scene, method, seed)


def run(a):
    os.makedirs(a.out, exist_ok=True)
    jobs = [(sc, me, sd) for sd in a.seeds for sc in a.scenes for me in METHODS]
    order = list(enumerate(jobs))
    if a.reverse:
        order.reverse()
    for i, (sc, me, sd) in order:
        if a.parts > 1 and i % a.parts != a.part:
            continue
        d = os.path.join(a.out, name(sc, me, sd))
        try:  # a job's log claims it: several processes share one list
            os.close(os.open(d + ".log", os.O_CREAT | os.O_EXCL))
        except FileExistsError:
            print("taken", d, flush=True)
            continue
        cmd = [a.train, "--task", "classify", "--snr-min", "-10", "--snr-max", "30", "--frames", "30000",
               "--batch", "256", "--threads", "1", "--seed", str(sd), "--eval-snr=" + SNRS, "--out", d,
               "--chirp-bins", "0", "--conv-slope", a.conv_slope]
        cmd += SCENES[sc] + METHODS[me]
        print("[%d/%d] %s" % (i + 1, len(jobs), " ".join(cmd)), flush=True)
        with open(d + ".log", "w") as log:
            subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, check=True)


def table(a):
    rows = {}
    for sc in a.scenes:
        print("\n%s scene (`--heading %s`), %d seeds:\n" % (sc, SCENES[sc][1], len(a.seeds)))
        print("| SNR (dB) | learned | Doppler pattern | learned - Doppler ± 2 SE | learned ≥ Doppler - 2 SE |")
        print("|---|---|---|---|---|")
        acc = {}
        for me in METHODS:
            for sd in a.seeds:
                b = json.load(open(os.path.join(a.out, name(sc, me, sd), "bundle.json")))
                for r in b["metrics"]["test_by_snr"]:
                    acc.setdefault((me, r["snr_min_db"]), []).append((r["accuracy"], r["frames"]))
        for snr in sorted({k[1] for k in acc}):
            le, do = acc[("learned", snr)], acc[("doppler", snr)]
            ml = sum(p for p, _ in le) / len(le)
            md = sum(p for p, _ in do) / len(do)
            var = sum(p * (1 - p) / n for p, n in le + do) / len(le) ** 2
            se2 = 2 * math.sqrt(var)
            ok = (ml - md) >= -se2
            print("| %g | %.3f | %.3f | %+.3f ± %.3f | %s |" % (snr, ml, md, ml - md, se2, "yes" if ok else "**no**"))
        for snr in (0.0,):
            print("\nAt %g dB per seed (%s): learned %s; Doppler pattern %s." % (
                snr, ", ".join(str(sd) for sd in a.seeds),
                " / ".join("%.3f" % p for p, _ in acc[("learned", snr)]),
                " / ".join("%.3f" % p for p, _ in acc[("doppler", snr)])))
        masks = []
        for sd in a.seeds:
            m = json.load(open(os.path.join(a.out, name(sc, "learned", sd), "mask.json")))
            sub = sorted({p[1] for p in m["pilots"]})
            sym = sorted({p[0] for p in m["pilots"]})
            masks.append("seed %d: %d subcarrier(s) %s x %d symbols" % (sd, len(sub), sub, len(sym)))
        print("\nLearned masks: " + "; ".join(masks) + ".")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["run", "table"])
    p.add_argument("--train", default="build/apps/sems_train")
    p.add_argument("--out", required=True)
    p.add_argument("--seeds", default="2026,2027,2028")
    p.add_argument("--scenes", default="default,any")
    p.add_argument("--part", type=int, default=0, help="run: this process's share (0..parts-1)")
    p.add_argument("--parts", type=int, default=1)
    p.add_argument("--reverse", action="store_true", help="run: take the jobs from the end")
    p.add_argument("--conv-slope", default="0", help="run: the convolutions' leaky-ReLU slope (0: plain ReLU)")
    a = p.parse_args()
    a.seeds = [int(s) for s in a.seeds.split(",")]
    a.scenes = a.scenes.split(",")
    run(a) if a.what == "run" else table(a)


if __name__ == "__main__":
    sys.exit(main())
