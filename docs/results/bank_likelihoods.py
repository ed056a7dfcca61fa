#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The template bank's likelihood against two others on the same templates, with no network:
whether the bank's way of scoring (the complex gain at its best, the noise estimated from the
frame) is what keeps "SemS + template bank" below the Bayes bound at low SNR, or the number of
templates.

A bank of T templates t (unit-gain noiseless frames of the scene, drawn from its prior) scores
a class by a likelihood of the frame y under each of the class's templates
(lib/learning/networks/template_bank.h). Three scores are compared on the same templates, test frames
and noise:

- known SNR: the Monte-Carlo Bayes classifier of the T draws, the noise variance s2 given,
  log p(y | t) = |t^H y|^2 / (s2 (s2 + |t|^2)) - log(1 + |t|^2 / s2) (classifier_bayes.py's
  body_loglik). No decoder is told the SNR; this is what the T templates allow at best.
- gain_max (the bank's): the complex gain at its best and the noise from the best match,
  beta = N_p / (1 - max rho), score log mean exp(beta rho_t), rho_t = |t^H y|^2 / (|t|^2 |y|^2).
- rayleigh: the exact likelihood when the SNR is not known: the Rayleigh gain averaged, as
  with the known SNR, the noise averaged over the training SNR range (uniform in dB, a grid
  2.5 dB apart) and the frame's overall scale c left unknown (y = c (alpha t + v), prior 1/c:
  a receiver's gains), with templates of the bank's mean power e / N_p:
  log p(y | t, s2) = log s2 + (N_p - 1) log(s2 + e) - N_p log(s2 + e (1 - rho_t)) + (terms
  common to every template and noise level).

The scene is experiment 7's (the kinematic class library, any heading, one Rayleigh path), the
mask the 32-pilot Doppler pattern, T = 24 000 (the training frames of the paper's budget):

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/bank_likelihoods.py \\
        --scene models/scenes/kinematic_any.json --templates 24000 --frames 3000 \\
        > docs/results/classifier_bayes/bank_likelihoods.log

Each cell is the accuracy over the test frames; the last columns are the paired differences
with two standard errors (from the frames the two decide differently).
"""
import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import classifier_bayes as cb  # noqa: E402  (the scene loader, the test frames, the Doppler pattern)



def class_log_means(ll, bounds):
    """B x K log-likelihoods -> B x C log mean exp over each class's (contiguous) templates."""
    out = []
    for c in range(len(bounds) - 1):
        seg = ll[:, bounds[c]:bounds[c + 1]]
        top = seg.max(1)
        out.append(top + np.log(np.exp(seg - top[:, None]).sum(1)) - math.log(seg.shape[1]))
    return np.stack(out, 1)


def scale_free_loglik(rho, e, s2, n_p):
    """log p(y | t, s2) of y = c (alpha g + v), g = sqrt(e) t / |t|, alpha ~ CN(0, 1),
    v ~ CN(0, s2 I), the scale c integrated out with the prior 1/c, as a function of
    rho = |t^H y|^2 / (|t|^2 |y|^2), but for terms common to every template and noise level
    (-N_p log |y|^2 and constants): log s2 + (N_p - 1) log(s2 + e) - N_p log(s2 + e (1 - rho))."""
    unexplained = np.float32(e) * (1 - np.minimum(rho, 1)).astype(np.float32)
    return -n_p * np.log(np.float32(s2) + unexplained) + np.float32(math.log(s2) + (n_p - 1) * math.log(s2 + e))


def noise_grid(lo, hi, step):
    steps = int(math.ceil((hi - lo) / step - 1e-9))
    snrs = [hi] if steps == 0 else [hi - (hi - lo) * j / steps for j in range(steps + 1)]
    return [10 ** (-s / 10) for s in snrs]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", required=True, help="a random scene of one target, one path, Rayleigh gain")
    ap.add_argument("--templates", type=int, default=24000, help="T, the bank's templates (prior draws)")
    ap.add_argument("--frames", type=int, default=3000, help="test frames")
    ap.add_argument("--pilots", type=int, default=32, help="N_p of the Doppler pattern")
    ap.add_argument("--snr", default="-10,-5,0,5,10,20,30", help="test SNR points (dB)")
    ap.add_argument("--train-snr", default="-10,30", help="the training SNR range the rayleigh bank averages over")
    ap.add_argument("--noise-step", type=float, default=2.5, help="rayleigh: the noise grid's largest step (dB)")
    ap.add_argument("--seed", type=int, default=20261125, help="test frames' seed; the templates' is seed + 1")
    a = ap.parse_args()
    if a.templates < 2 or a.frames < 1:
        ap.error("--templates must be >= 2 and --frames >= 1")
    lo, hi = (float(x) for x in a.train_snr.split(","))
    if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
        ap.error("--train-snr must be a finite range min,max")
    from gnuradio import sems

    t0 = time.time()
    fs = sems.frame_settings()
    scene, unit = cb.load_scene(sems, a.scene)
    names = [scene.class_name(c) for c in scene.label_classes()]
    idx = np.array(cb.pattern_mask(sems, "doppler", fs, a.pilots).flat_indices())
    n_p = len(idx)
    test, truth, _ = cb.draw_scene_test(sems, scene, fs, [idx], names, a.frames, a.seed)
    test = test[0]
    h, truths = sems.channel_model(fs, unit, a.seed + 1).generate(a.templates, 0)
    sig = np.asarray(h).reshape(a.templates, -1)[:, idx].astype(np.complex64)
    cls = np.array([names.index(t["class_name"]) for t in truths])
    order = np.argsort(cls, kind="stable")
    sig, cls = sig[order], cls[order]
    bounds = np.searchsorted(cls, np.arange(len(names) + 1))
    rng = np.random.default_rng(a.seed + 2)
    noise = ((rng.standard_normal(test.shape, dtype=np.float32)
              + 1j * rng.standard_normal(test.shape, dtype=np.float32)) / np.sqrt(2)).astype(np.complex64)
    energy = np.sum(np.abs(sig) ** 2, 1).astype(np.float32)  # |t|^2 per template
    e_bank = float(np.mean(energy))  # rayleigh: N_p times the bank's mean power per pilot
    if not a.noise_step > 0:
        ap.error("--noise-step must be > 0")
    grid = noise_grid(lo, hi, a.noise_step)
    print("bank_likelihoods: scene %s (classes %s), Doppler pattern of %d pilots, %d templates (per class %s), "
          "%d test frames; rayleigh averages over %d noise levels from %g to %g dB"
          % (a.scene, ", ".join(names), n_p, a.templates, "/".join(map(str, np.diff(bounds))), a.frames,
             len(grid), lo, hi), flush=True)
    print("%6s %10s %10s %10s %22s %22s" % ("SNR dB", "known SNR", "gain_max", "rayleigh",
                                              "rayleigh - gain_max", "known SNR - rayleigh"))
    for snr in [float(s) for s in a.snr.split(",")]:
        s2 = 10 ** (-snr / 10)
        right = {"known": [], "gain_max": [], "rayleigh": []}
        for first in range(0, a.frames, 250):
            y = (test[first:first + 250] + np.float32(math.sqrt(s2)) * noise[first:first + 250]).astype(np.complex64)
            z = y @ sig.conj().T
            q = (z.real ** 2 + z.imag ** 2).astype(np.float32)  # |t^H y|^2
            y2 = np.sum(y.real ** 2 + y.imag ** 2, 1).astype(np.float32)
            want = truth[first:first + 250]
            known = class_log_means(q / (s2 * (s2 + energy))[None, :] - np.log1p(energy / s2)[None, :], bounds)
            rho = q / energy[None, :] / y2[:, None]
            beta = n_p / np.maximum(1 - np.clip(rho.max(1, keepdims=True), 0, 1), 1e-3)
            gain_max = class_log_means(beta * rho, bounds)
            ray = None
            for g in grid:
                sj = class_log_means(scale_free_loglik(rho, e_bank, g, n_p), bounds).astype(np.float64)
                ray = sj if ray is None else np.logaddexp(ray, sj)
            for k, s in (("known", known), ("gain_max", gain_max), ("rayleigh", ray)):
                right[k].append(s.argmax(1) == want)
        right = {k: np.concatenate(v).astype(float) for k, v in right.items()}

        def diff(x, y):
            d = right[x] - right[y]
            return "%+.4f ± %.4f" % (d.mean(), 2 * d.std() / math.sqrt(len(d)))

        print("%6g %10.4f %10.4f %10.4f %22s %22s" % (
            snr, right["known"].mean(), right["gain_max"].mean(), right["rayleigh"].mean(),
            diff("rayleigh", "gain_max"), diff("known", "rayleigh")), flush=True)
    print("done in %.0f s" % (time.time() - t0))


if __name__ == "__main__":
    main()
