#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Several classifier bundles on the same fresh frames and noise, each against the first
(difference and two paired standard errors): what docs/RESULTS.md uses to compare networks
of one scene more finely than experiment 1's 3 000 test frames allow.

The frames come from the project's own channel model (the random scene of --heading, channel
seed 4242, which no training run or experiment uses); the noise is drawn once per batch with
unit variance and scaled per SNR, so every bundle and SNR sees the same channels and noise.
Each bundle reads its own mask's pilots.

    PYTHONPATH=build/python_pkg OMP_NUM_THREADS=1 /usr/bin/python3 docs/results/score_classifiers.py \\
        --heading any --snr=-5,0,10,30 --frames 30000 BUNDLE [BUNDLE ...]
"""
import argparse
import os

import numpy as np

from gnuradio import sems
from gnuradio.sems.datasets import channel_batches


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bundles", nargs="+", help="classifier bundle directories (the first is the reference)")
    ap.add_argument("--heading", default="approaching", choices=["approaching", "any"])
    ap.add_argument("--snr", default="0,10", help="SNR points (dB), comma-separated")
    ap.add_argument("--frames", type=int, default=30000, help="frames (a multiple of 1000)")
    ap.add_argument("--seed", type=int, default=4242, help="channel seed")
    a = ap.parse_args()
    if a.frames < 1000 or a.frames % 1000:
        ap.error("--frames must be a positive multiple of 1000, got %d" % a.frames)
    snrs = [float(s) for s in a.snr.split(",")]
    decs = []
    for b in a.bundles:
        m = sems.model_bundle.load(b)
        decs.append((b, sems.bundle_decoder(m, 1), np.array(m.mask.flat_indices()), list(m.class_names)))
    names = decs[0][3]
    for b, _, _, n in decs[1:]:
        if n != names:
            ap.error("%s has classes %s, %s has %s" % (b, n, a.bundles[0], names))
    spec = sems.random_spec()
    spec.heading = sems.heading_from_name(a.heading)
    correct = {(b, s): [] for b in a.bundles for s in snrs}
    for batch, (h, t) in enumerate(channel_batches(sems.scene.random(spec), 1000, a.frames // 1000, seed=a.seed)):
        hf = h.reshape(len(t), -1)
        y = np.array([names.index(x["class_name"]) for x in t])
        rng = np.random.default_rng(batch)
        w = (rng.standard_normal(hf.shape) + 1j * rng.standard_normal(hf.shape)) / np.sqrt(2)
        for s in snrs:
            sigma = 10 ** (-s / 20)
            for b, dec, idx, _ in decs:
                obs = (hf[:, idx] + sigma * w[:, idx]).astype(np.complex64)
                correct[(b, s)].append(dec.classify(obs).argmax(1) == y)
    print("score_classifiers: %s heading, %d frames (channel seed %d); accuracy, and against %s: "
          "difference ± 2 paired SE" % (a.heading, a.frames, a.seed, a.bundles[0]))
    for s in snrs:
        ref = np.concatenate(correct[(a.bundles[0], s)]).astype(float)
        cells = []
        for b in a.bundles:
            v = np.concatenate(correct[(b, s)]).astype(float)
            d = v - ref
            cells.append("%s %.4f (%+.4f ± %.4f)" % (os.path.basename(os.path.normpath(b)), v.mean(), d.mean(),
                                                      2 * d.std() / np.sqrt(len(d))))
        print("%6g dB: %s" % (s, "  ".join(cells)), flush=True)


if __name__ == "__main__":
    main()
