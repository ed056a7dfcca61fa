#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Where a classifier bundle's errors sit: accuracy by the frame's pilot power |alpha|^2 and by
its radial Doppler.

One path with a Rayleigh gain gives every pilot the same fade, so a frame's pilot power (the
mean |H|^2 over the mask, 1 on average) is its SNR offset. This prints the confusion matrix
and the accuracy per pilot-power bin at one SNR, on frames of the bundle's default random
scene that no training run used (channel seed 777, noise from numpy's generator):

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/classifier_errors_by_fade.py \
        --bundle models/classifier --snr 10 --frames 10000

--heading any draws the `any` heading scene instead (docs/RESULTS.md, "The best any decoder can
do": where the spectral decoder's errors sit at high SNR).
"""
import argparse

import numpy as np

from gnuradio import sems
from gnuradio.sems.datasets import channel_batches

BINS = [(0, 0.01), (0.01, 0.03), (0.03, 0.1), (0.1, 0.3), (0.3, 1.0), (1.0, np.inf)]
DOPPLER_BINS_HZ = [(0, 10), (10, 40), (40, 100), (100, 200), (200, 400), (400, np.inf)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bundle", required=True, help="classifier bundle directory")
    ap.add_argument("--snr", type=float, default=10.0, help="SNR per resource element (dB)")
    ap.add_argument("--frames", type=int, default=10000, help="frames (a multiple of 1000)")
    ap.add_argument("--heading", default="approaching", choices=["approaching", "any"], help="the random scene's heading")
    a = ap.parse_args()
    if a.frames < 1000 or a.frames % 1000:
        ap.error("--frames must be a positive multiple of 1000, got %d" % a.frames)
    bundle = sems.model_bundle.load(a.bundle)
    dec = sems.bundle_decoder(bundle, 1)
    idx = np.array(bundle.mask.flat_indices())
    names = list(bundle.class_names)
    sigma = 10 ** (-a.snr / 20)
    spec = sems.random_spec()
    spec.heading = sems.heading_from_name(a.heading)
    fs = sems.frame_settings()
    truth, pred, power, doppler = [], [], [], []
    for batch, (h, t) in enumerate(channel_batches(sems.scene.random(spec), 1000, a.frames // 1000, seed=777)):
        hp = h.reshape(len(t), -1)[:, idx]
        rng = np.random.default_rng(batch)
        w = (rng.standard_normal(hp.shape) + 1j * rng.standard_normal(hp.shape)) / np.sqrt(2)
        pred.append(dec.classify((hp + sigma * w).astype(np.complex64)).argmax(1))
        truth.append([names.index(x["class_name"]) for x in t])
        power.append(np.mean(np.abs(hp) ** 2, axis=1))
        doppler.append([fs.doppler_from_velocity(x["velocity_mps"]) for x in t])
    y, p, g = np.concatenate(truth), np.concatenate(pred), np.concatenate(power)
    fd = np.abs(np.concatenate(doppler))
    print("%s at %g dB on %d frames: accuracy %.4f" % (a.bundle, a.snr, len(y), np.mean(y == p)))
    print("confusion (rows: truth, columns: predicted):", names)
    conf = np.zeros((len(names), len(names)), int)
    np.add.at(conf, (y, p), 1)
    print(conf)
    for lo, hi in BINS:
        s = (g >= lo) & (g < hi)
        acc = np.mean(y[s] == p[s]) if s.any() else float("nan")
        print("pilot power [%g, %g): %5d frames (%.4f), accuracy %.4f, %d errors" % (lo, hi, s.sum(), s.mean(), acc,
                                                                                   np.sum(y[s] != p[s])))
    for lo, hi in DOPPLER_BINS_HZ:
        s = (fd >= lo) & (fd < hi)
        if s.any():
            print("|bulk Doppler| [%g, %g) Hz: %5d frames, accuracy %.4f, errors by true class %s" % (
                lo, hi, s.sum(), np.mean(y[s] == p[s]),
                dict(zip(names, np.bincount(y[s & (y != p)], minlength=len(names)).tolist()))))


if __name__ == "__main__":
    main()
