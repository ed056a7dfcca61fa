#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The least delay MAE any estimator can reach on a single-path bundle's mask, next to the
bundle and the fading-averaged CRB of the bundle's own mask.

For one path with Rayleigh gain the posterior of the delay is known in closed form: with
pilots y_s = alpha exp(-j 2 pi m_s tau / M) + v_s on one symbol, alpha ~ CN(0, 1) and
v_s ~ CN(0, sigma^2), y is zero-mean Gaussian given tau, and

    p(tau | y) ∝ p(tau) exp(|a(tau)^H y|^2 / (sigma^2 (sigma^2 + N_p)))

(|a|^2 = N_p). The posterior median minimises the expected absolute error frame by frame,
so its mean absolute error over frames drawn from the model is the minimum MAE of *any*
estimator on that mask (the Bayes bound for the absolute error), up to the grid and the
Monte-Carlo error printed beside it. The frames come from the project's own channel model
(`sems.channel_model`, the random single-path scene `sems_train --paths 1` trains on, its
micro-Doppler a common phase on one symbol), the delay prior is the scene's (uniform over
the range interval, read off the frames), and the same frames go through the bundle.

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/single_path_bayes.py \
        --bundle models/delay_single --frames 100000 --snr 10,20,30

Further bundles on the same mask (--bundle again) get a column each on the same frames;
--without-global-peak adds the first bundle with refine_global_peak off (its copy in a
temporary directory), the decoder as it was before that setting.

--mask FILE (repeatable; one-symbol pilot masks, mask.json format) computes the bound and ML
on each of those masks instead of a bundle's, on the same channels and noise for every mask:
how the ratio to the CRB moves with the mask (a contiguous block of subcarriers has a larger
CRB and fewer sidelobes than a spread one), e.g.

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/single_path_bayes.py \
        --mask models/delay_single/mask.json --mask contiguous.json --frames 100000 --snr 20
"""
import argparse
import json
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np


def frames_of(sems, fs, mask_sub, mask_sym, n, seed, chunk=4000):
    """Noiseless pilots (n x N_p), the true delay index and |alpha|^2 of n frames."""
    cm = sems.channel_model(fs, sems.scene.random(), seed)
    pil, tau, gain = [], [], []
    done = 0
    while done < n:
        k = min(chunk, n - done)
        h, truths = cm.generate(k)
        h = np.asarray(h)
        p = h[:, mask_sym, mask_sub]
        pil.append(p.astype(np.complex64))
        tau.append([t["delay_index"] for t in truths])
        gain.append(np.abs(p[:, 0]) ** 2)  # one path: |H| = |alpha| on every subcarrier of the symbol
        done += k
    return np.concatenate(pil), np.concatenate(tau), np.concatenate(gain)


def noisy(clean, snr, rng):
    """The pilots with CN(0, sigma^2) noise at `snr` dB per resource element, and sigma^2."""
    sigma2 = 10 ** (-snr / 10)
    noise = (rng.standard_normal(clean.shape) + 1j * rng.standard_normal(clean.shape)) * math.sqrt(sigma2 / 2)
    return (clean + noise).astype(np.complex64), sigma2


def bayes_and_ml(y, sub, m, sigma2, lo, hi, spacing, chunk=400):
    """Posterior median and maximum (grid + parabola) of the delay index, uniform prior on [lo, hi]."""
    grid = np.arange(lo, hi + spacing / 2, spacing)
    # conj(a): the conjugate of core/array/steering.h's delay_phasor(m, tau, M) = exp(-j 2 pi m tau / M),
    # which has no Python binding; written out as the Python tests do (qa_baselines.py).
    steer_conj = np.exp(2j * np.pi * np.outer(sub, grid) / m).astype(np.complex64)  # N_p x G
    kappa = 1.0 / (sigma2 * (sigma2 + len(sub)))
    med, ml = np.empty(len(y)), np.empty(len(y))
    for i in range(0, len(y), chunk):
        z = y[i:i + chunk] @ steer_conj                      # a(tau)^H y on the grid
        ll = (z.real ** 2 + z.imag ** 2).astype(np.float64) * kappa
        top = ll.argmax(1)
        rows = np.arange(len(ll))
        # ML: parabola through the grid maximum and its neighbours
        l0 = ll[rows, np.maximum(top - 1, 0)]
        l1 = ll[rows, top]
        l2 = ll[rows, np.minimum(top + 1, len(grid) - 1)]
        den = l0 - 2 * l1 + l2
        off = np.where(den < 0, 0.5 * (l0 - l2) / np.where(den < 0, den, -1), 0.0)
        ml[i:i + chunk] = grid[top] + np.clip(off, -0.5, 0.5) * spacing
        # Posterior median: the CDF of the (trapezoid-integrated) posterior crosses 1/2
        w = np.exp(ll - l1[:, None])
        cdf = np.cumsum(0.5 * (w[:, 1:] + w[:, :-1]), axis=1)
        cdf /= cdf[:, -1:]
        j = (cdf < 0.5).sum(1)                                # first interval where the CDF reaches 1/2
        c0 = np.where(j > 0, cdf[rows, np.maximum(j - 1, 0)], 0.0)
        c1 = cdf[rows, j]
        frac = np.where(c1 > c0, (0.5 - c0) / (c1 - c0), 0.5)
        med[i:i + chunk] = grid[j] + frac * spacing
    return med, ml


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bundle", action="append", help="single-path delay bundle (repeatable; default "
                    "models/delay_single); the first one's mask is used")
    ap.add_argument("--mask", action="append", default=[],
                    help="one-symbol pilot mask file (repeatable): the bound and ML on each, no bundle")
    ap.add_argument("--without-global-peak", action="store_true",
                    help="also the first bundle with decoder.settings.refine_global_peak = false")
    ap.add_argument("--frames", type=int, default=200000)
    ap.add_argument("--snr", default="10,20,30")
    ap.add_argument("--spacing", type=float, default=0.0005, help="posterior grid spacing (delay index)")
    ap.add_argument("--seed", type=int, default=20261124)
    args = ap.parse_args()
    from gnuradio import sems

    if args.mask:
        if args.bundle or args.without_global_peak:
            sys.exit("single_path_bayes: --mask scores masks only; leave out --bundle and --without-global-peak")
        return masks_only(sems, args)
    bundles = args.bundle or ["models/delay_single"]
    labels = [os.path.basename(os.path.normpath(b)) for b in bundles]
    tmp = tempfile.mkdtemp()
    if args.without_global_peak:  # as apps/benchmarks/torch_reference.py's with_refinement_off, for another key
        copy = os.path.join(tmp, "without_global_peak")
        shutil.copytree(bundles[0], copy)
        with open(os.path.join(copy, "bundle.json")) as f:
            info = json.load(f)
        info["decoder"]["settings"]["refine_global_peak"] = False
        with open(os.path.join(copy, "bundle.json"), "w") as f:
            json.dump(info, f, indent=2)
        bundles.append(copy)
        labels.append(labels[0] + " (no global peak)")
    fs = sems.frame_settings()
    mask = sems.pilot_mask.load(bundles[0] + "/mask.json")
    pos = mask.positions()
    sym, sub = one_symbol(bundles[0] + "/mask.json", mask)
    decs = [sems.bundle_decoder(b, 1) for b in bundles]
    for b, d in zip(bundles[1:], decs[1:]):
        other = sems.pilot_mask.load(b + "/mask.json").positions()
        if other != pos:
            sys.exit("single_path_bayes: %s has another mask than %s" % (b, bundles[0]))
    t0 = time.time()
    clean, tau, gain = frames_of(sems, fs, sub, sym, args.frames, args.seed)
    lo, hi = float(np.floor(tau.min())), float(np.ceil(tau.max()))
    print("single_path_bayes: %s, %d pilots on symbol %d, %d frames per SNR; delay index of the "
          "frames %.3f..%.3f (prior uniform on [%g, %g]); mean |alpha|^2 %.4f; grid spacing %g"
          % (bundles[0], len(sub), sym, len(tau), tau.min(), tau.max(), lo, hi, gain.mean(), args.spacing),
          flush=True)
    rng = np.random.default_rng(args.seed + 1)
    print("bundles: " + "; ".join("[%d] %s" % (i, l) for i, l in enumerate(labels)))
    print("%6s %10s %10s %8s %10s %8s" % ("SNR dB", "CRB MAE", "Bayes MAE", "/CRB", "ML MAE", "/CRB")
          + "".join(" %10s %8s" % ("[%d] MAE" % i, "/CRB") for i in range(len(bundles)))
          + " %12s" % "Bayes 2 SE")
    for snr in [float(s) for s in args.snr.split(",")]:
        y, sigma2 = noisy(clean, snr, rng)
        med, ml = bayes_and_ml(y, sub, fs.n_subcarriers, sigma2, lo, hi, args.spacing)
        e_nets = []
        for dec in decs:
            net = np.concatenate([np.asarray(dec.estimate_delay_index(y[i:i + 256]))
                                  for i in range(0, len(y), 256)])
            e_nets.append(np.abs(net - tau))
        crb = sems.delay_crb.mae_index(fs, mask, snr)
        e_b, e_ml = np.abs(med - tau), np.abs(ml - tau)
        se = e_b.std() / math.sqrt(len(e_b))
        print("%6g %10.5f %10.5f %7.2fx %10.5f %7.2fx" % (snr, crb, e_b.mean(), e_b.mean() / crb, e_ml.mean(),
                                                          e_ml.mean() / crb)
              + "".join(" %10.5f %7.2fx" % (e.mean(), e.mean() / crb) for e in e_nets)
              + " %12.5f" % (2 * se), flush=True)
        print("       medians: Bayes %.5f  ML %.5f" % (np.median(e_b), np.median(e_ml))
              + "".join("  [%d] %.5f" % (i, np.median(e)) for i, e in enumerate(e_nets))
              + "; frames off by > 0.5 index: Bayes %.3f %%  ML %.3f %%" % (100 * (e_b > 0.5).mean(),
                                                                              100 * (e_ml > 0.5).mean())
              + "".join("  [%d] %.3f %%" % (i, 100 * (e > 0.5).mean()) for i, e in enumerate(e_nets))
              + "; Bayes MAE of the frames with |alpha|^2 >= 0.01: %.5f" % e_b[gain >= 0.01].mean(), flush=True)
    shutil.rmtree(tmp)
    print("single_path_bayes: done in %.0f s" % (time.time() - t0))


def one_symbol(path, mask):
    """The pilot symbol and subcarriers of a one-symbol mask, or exit naming the file."""
    pos = mask.positions()
    syms = {n for n, _ in pos}
    if len(syms) != 1:
        sys.exit("single_path_bayes: %s spans symbols %s; this bound needs pilots on one symbol "
                 "(an unknown Doppler phase per symbol otherwise)" % (path, sorted(syms)))
    return syms.pop(), np.array([m for _, m in pos])


def masks_only(sems, args):
    """The bound, ML and the CRB on each --mask, the same channels and noise for every mask."""
    fs = sems.frame_settings()
    t0 = time.time()
    print("single_path_bayes: %d masks, %d frames per SNR, grid spacing %g; the same channels (seed %d) "
          "and noise for every mask" % (len(args.mask), args.frames, args.spacing, args.seed), flush=True)
    print("%-40s %6s %10s %10s %8s %10s %8s %12s %10s" % ("mask", "SNR dB", "CRB MAE", "Bayes MAE", "/CRB",
                                                         "ML MAE", "/CRB", "Bayes 2 SE", "> 0.5 idx"))
    for path in args.mask:
        mask = sems.pilot_mask.load(path)
        sym, sub = one_symbol(path, mask)
        clean, tau, _ = frames_of(sems, fs, sub, sym, args.frames, args.seed)
        lo, hi = float(np.floor(tau.min())), float(np.ceil(tau.max()))
        rng = np.random.default_rng(args.seed + 1)
        for snr in [float(s) for s in args.snr.split(",")]:
            y, sigma2 = noisy(clean, snr, rng)
            med, ml = bayes_and_ml(y, sub, fs.n_subcarriers, sigma2, lo, hi, args.spacing)
            crb = sems.delay_crb.mae_index(fs, mask, snr)
            e_b, e_ml = np.abs(med - tau), np.abs(ml - tau)
            print("%-40s %6g %10.5f %10.5f %7.2fx %10.5f %7.2fx %12.5f %9.3f%%" % (
                os.path.basename(os.path.dirname(path)) + "/" + os.path.basename(path) if "/" in path else path,
                snr, crb, e_b.mean(), e_b.mean() / crb, e_ml.mean(), e_ml.mean() / crb,
                2 * e_b.std() / math.sqrt(len(e_b)), 100 * (e_b > 0.5).mean()), flush=True)
    print("single_path_bayes: done in %.0f s" % (time.time() - t0))


if __name__ == "__main__":
    main()
