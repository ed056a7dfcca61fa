#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The highest recognition accuracy any decoder can reach on a pilot mask (the Bayes
classifier), next to a bundle and other masks on the same frames: how far a bundle is from what its
pilots allow, and whether another mask could do better.

One target with one path and a Rayleigh gain: a frame's pilots are y = alpha g_theta + v, with
g_theta the unit-modulus signature of the scene parameters theta (delay phase per subcarrier,
bulk Doppler, micro-Doppler phase per symbol; |g|^2 = N_p), alpha ~ CN(0, 1), v ~ CN(0, s2 I).
Given theta, y is zero-mean Gaussian with covariance s2 I + g g^H, so

    p(y | theta) ∝ exp(|g_theta^H y|^2 / (s2 (s2 + N_p)))

(the factors that do not depend on theta dropped), and the class posterior is the mean of that
over the class's prior of theta. This script draws the prior from the project's own channel
model (`sems.channel_model`, the random scene the classifiers train on: K noiseless frames, the
signature of each = its pilots / |alpha|), and classifies each test frame by the largest
Monte-Carlo mean (classes equally likely, as the scene draws them). With enough prior draws
that is the Bayes classifier: the most accurate decoder there is for the mask. A Monte-Carlo
classifier is itself a decoder, so its accuracy is reachable and at most the Bayes accuracy;
the script prints it with all K draws and with the first half of each class's, and when the
two agree (within one binomial standard error of the test frames) the Monte-Carlo mean has
converged and the printed accuracy is the bound; where they do not (marked `!`: at high SNR
the likelihood peaks between the draws), it is only a lower estimate (still reachable: the
classifier is a decoder), and its --csv row is named so.

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/classifier_bayes.py \
        --mask doppler --label doppler --bundle models/classifier --heading approaching \
        --snr=-10,-5,0,5,10,15,20,25,30 --frames 30000 --prior 40000 \
        --csv docs/results/bound_exp1_recognition.csv

A --mask is a mask file or a pattern: `doppler`, `uniform`, `random` (the hand patterns of
docs/RESULTS.md, --pilots pilots, or N with `doppler:N`) or `blocks:S,K[,ds[,dm]]` (subcarriers 16, 16 + dm, ...,
S of them (dm default 1: adjacent), each on symbols 0, ds, ..., (K - 1) ds (ds default 1)).
The more scene parameters a mask's pilots depend on (the delay, on several subcarriers), the
more prior draws the mean needs: read the all / half columns. --bundle scores a classifier
bundle on the same noisy frames (on its own mask). Every mask and bundle sees the same
channels, and the same noise on the resource elements they share. --csv writes the Bayes rows
in sems_eval's experiment-1 columns; apps/figures/plot_results.py draws them as `bound_<csv>`.

--scene FILE replaces the paper's scene by a scene file of one random target with one path and
a Rayleigh gain whose class library makes targets bodies of scatterers (the kinematic library:
models/scenes/kinematic_any.json). A body's g_theta is not unit-modulus, so the likelihood keeps
the determinant term (body_loglik); g_theta is the noiseless frame of the same scene with a unit
gain ("fading": "none"), and the prior is streamed in chunks (bayes_scene), so memory does not
grow with --prior. Its --csv rows add the accuracy with half the draws and the converged flag:

    PYTHONPATH=build/python_pkg /usr/bin/python3 docs/results/classifier_bayes.py \
        --scene models/scenes/kinematic_any.json --mask doppler --label doppler \
        --snr=-10,-5,0,5,10,15,20,25,30 --frames 3000 --prior 120000 \
        --csv docs/results/bound_kinematic.csv
"""
import argparse
import csv
import json
import math
import os
import time

import numpy as np

BINS = [(0, 0.01), (0.01, 0.03), (0.03, 0.1), (0.1, np.inf)]
METHOD = "Bayes classifier (bound)"
METHOD_UNCONVERGED = "Bayes classifier, not converged (reachable, below the bound)"
# --as-decoder: the Monte-Carlo classifier of a given prior size, a decoder and never the bound
METHOD_DRAWS = "Bayes classifier from %s prior draws (a decoder)"


def method_family(method):
    """Rows of the bound (converged or not) and rows of a decoder of a given prior size replace
    only rows of their own kind (and size) in a --csv file."""
    return method if method.startswith("Bayes classifier from") else "bound"


def pattern_mask(sems, name, fs, n_p):
    """A mask file, or a named pattern of n_p pilots on the default frame."""
    n, m = fs.n_symbols, fs.n_subcarriers
    base, _, count = name.partition(":")
    if base in ("doppler", "uniform", "random"):
        if count:  # doppler:128: the pattern with 128 pilots
            if not count.isdigit() or int(count) < 1:
                raise ValueError("%s: a pattern's pilot count is a positive integer (e.g. doppler:128)" % name)
            n_p = int(count)
        return sems.pilot_mask.from_pattern(base, n, m, n_p, 1)  # random: seed 1, as docs/RESULTS.md
    if name.startswith("blocks:"):
        # blocks:S,K[,ds[,dm]]: S subcarriers 16, 16 + dm, ... (dm 1: adjacent), each with the
        # K symbols 0, ds, 2 ds, ... (ds 1: consecutive)
        v = [int(x) for x in name[len("blocks:"):].split(",")]
        if len(v) < 2 or len(v) > 4 or min(v) < 1:
            raise ValueError("%s: a blocks pattern is blocks:S,K[,ds[,dm]] with positive integers" % name)
        s, k, ds, dm = (v + [1, 1])[:4]
        if 16 + (s - 1) * dm >= m or (k - 1) * ds >= n:
            raise ValueError("%s: does not fit the %d x %d grid" % (name, n, m))
        return sems.pilot_mask(n, m, [(t * ds, 16 + c * dm) for c in range(s) for t in range(k)])
    return sems.pilot_mask.load(name)


def draw(sems, scene, masks, n, seed, chunk=2000):
    """n noiseless frames of the channel model (seed): per mask the pilots (n x N_p), the class
    indices and |alpha|^2."""
    from gnuradio.sems.datasets import channel_batches
    names = list(sems.class_names())
    pil = [[] for _ in masks]
    cls = []
    for h, truths in channel_batches(scene, chunk, -(-n // chunk), seed=seed):
        h = np.asarray(h).reshape(len(truths), -1)
        for i, idx in enumerate(masks):
            pil[i].append(h[:, idx].astype(np.complex64))
        cls += [names.index(t["class_name"]) for t in truths]
    pil = [np.concatenate(p)[:n] for p in pil]
    gain = np.mean(np.abs(pil[0]) ** 2, axis=1)  # one path: |H| = |alpha| everywhere
    return pil, np.array(cls[:n]), gain


def bayes_classify(y, sig, sig_cls, n_cls, s2, chunk=256):
    """Monte-Carlo Bayes decisions with all prior draws and with the first half of each class's.

    log p(y | c) = log mean_k exp(kappa |g_k^H y|^2) over the class's draws k, computed per
    class from its largest term (float32 is enough: the terms are summed after that shift).
    Noiseless (s2 = 0) the mean's limit is its largest term: the nearest draw."""
    n_p = y.shape[1]
    kappa = np.float32(1.0 / (s2 * (s2 + n_p))) if s2 > 0 else None
    order = np.argsort(sig_cls, kind="stable")  # each class's draws contiguous, in draw order
    bounds = np.searchsorted(sig_cls[order], np.arange(n_cls + 1))
    sig_h = np.ascontiguousarray(sig[order].conj().T)  # N_p x K
    full, half = np.empty(len(y), int), np.empty(len(y), int)
    for i in range(0, len(y), chunk):
        z = y[i:i + chunk] @ sig_h
        ll = np.square(z.real) + np.square(z.imag)
        if kappa is not None:
            ll *= kappa
        lf, lh = [], []
        for c in range(n_cls):
            lo, hi = bounds[c], bounds[c + 1]
            mid = lo + (hi - lo) // 2
            top = ll[:, lo:hi].max(1)
            if kappa is None:
                lf.append(top)
                lh.append(ll[:, lo:mid].max(1))
                continue
            e = np.exp(ll[:, lo:hi] - top[:, None])
            s_half, s_rest = e[:, :mid - lo].sum(1), e[:, mid - lo:].sum(1)
            lf.append(top + np.log(s_half + s_rest) - np.log(hi - lo))
            with np.errstate(divide="ignore"):  # a half whose terms all underflow: log 0 = -inf, never chosen
                lh.append(top + np.log(s_half) - np.log(mid - lo))
        full[i:i + chunk] = np.stack(lf, 1).argmax(1)
        half[i:i + chunk] = np.stack(lh, 1).argmax(1)
    return full, half


def load_scene(sems, path):
    """A scene file of one random target with one path and a Rayleigh gain, and the same scene
    with a unit gain (fading none, the same library): its noiseless frames are the signatures
    g_theta, drawn from the same prior of theta."""
    sc = sems.scene.load(path)
    d = json.loads(sc.to_json_string())
    r = d.get("random")
    problems = []
    if r is None:
        problems.append("is a fixed scene (a random one is needed: the prior is its draws)")
    else:
        if r["targets"] != 1:
            problems.append("draws %d targets (one is needed)" % r["targets"])
        if r["paths_per_target"] != 1:
            problems.append("draws %d paths per target (one is needed)" % r["paths_per_target"])
    if "clutter" in d:
        problems.append("has clutter (none is allowed)")
    if d["fading"] != "rayleigh":
        problems.append("has fading '%s' (the likelihood needs a Rayleigh gain)" % d["fading"])
    if problems:
        raise ValueError("%s: %s: the Bayes classifier here models y = alpha g_theta + v, one target, one "
                         "path, alpha ~ CN(0, 1)" % (path, "; ".join(problems)))
    d["fading"] = "none"
    unit = sems.scene.parse(json.dumps(d), path + " (unit gain)").with_library(sc.library())
    return sc, unit


def draw_scene_test(sems, sc, fs, masks, names, n, seed):
    """n noiseless test frames of the scene (seed): per mask the pilots (n x N_p), the class
    indices and |alpha|^2 (the drawn gain: a body's |H| varies over the grid)."""
    model = sems.channel_model(fs, sc, seed)
    pil = [np.empty((n, len(idx)), np.complex64) for idx in masks]
    cls, gain = np.empty(n, int), np.empty(n)
    for f in range(n):
        r = model.draw(f)
        h = np.asarray(model.channel(r, f * fs.n_symbols)).reshape(-1)
        for i, idx in enumerate(masks):
            pil[i][f] = h[idx]
        cls[f] = names.index(r.truth["class_name"])
        gain[f] = abs(r.paths[0].gain) ** 2
    return pil, cls, gain


def body_loglik(y, sig, s2):
    """log p(y | theta) up to terms common to every theta, for y = alpha g + v with alpha ~ CN(0, 1)
    and v ~ CN(0, s2 I), i.e. y | theta ~ CN(0, s2 I + g g^H):

        log p = -log(1 + |g|^2 / s2) + |g^H y|^2 / (s2 (s2 + |g|^2))   [- N_p log(pi s2) - |y|^2 / s2]

    y: T x N_p, sig: K x N_p (the draws' g); returns T x K (float32). s2 = 0 (noiseless): the limit's
    ordering, |g^H y|^2 / |g|^2 (the draw whose direction is nearest)."""
    e = np.sum(np.square(sig.real) + np.square(sig.imag), axis=1, dtype=np.float64)
    z = y @ sig.conj().T
    q = np.square(z.real) + np.square(z.imag)
    if s2 == 0:
        return q * (1.0 / e).astype(np.float32)
    return q * (1.0 / (s2 * (s2 + e))).astype(np.float32) - np.log1p(e / s2).astype(np.float32)


def bayes_scene(sems, unit, fs, masks, names, clean, noise, s2s, n_prior, seed, chunk=2000, cells=1 << 22):
    """Monte-Carlo Bayes decisions for a scene of bodies: every mask, every noise variance in s2s,
    with all n_prior draws of the unit-gain scene (seed) and with those of the first half.

    The prior is drawn in chunks and never kept: per test frame, class and half, a running
    log-sum-exp of log p(y | theta) (its largest term and the sum of the terms relative to
    it; noiseless, the largest term alone). Memory: a chunk's frames and a test tile x chunk
    block of at most `cells` values. Returns {(mask, s2): (full, half)} and the draws per class."""
    n_cls, n_test = len(names), len(clean[0])
    # running (largest term, sum) per mask, s2, half, test frame, class
    top = np.full((len(masks), len(s2s), 2, n_test, n_cls), -np.inf)
    acc = np.zeros_like(top)
    counts = np.zeros((2, n_cls), int)
    tile = max(1, min(n_test, cells // chunk))
    model = sems.channel_model(fs, unit, seed)
    t0, last = time.time(), 0.0
    for first in range(0, n_prior, chunk):
        m = min(chunk, n_prior - first)
        h, truths = model.generate(m, first)
        h = np.asarray(h).reshape(m, -1)
        cls = np.array([names.index(t["class_name"]) for t in truths])
        # the first half of the draws (by draw order) and the rest
        mid = min(max(n_prior // 2 - first, 0), m)
        for half, (lo, hi) in enumerate([(0, mid), (mid, m)]):
            if lo == hi:
                continue
            order = lo + np.argsort(cls[lo:hi], kind="stable")  # each class's draws contiguous
            bounds = np.searchsorted(cls[order], np.arange(n_cls + 1))
            counts[half] += np.diff(bounds)
            for i, idx in enumerate(masks):
                sig = h[np.ix_(order, idx)]
                for a in range(0, n_test, tile):
                    b = min(n_test, a + tile)
                    for j, s2 in enumerate(s2s):
                        y = clean[i][a:b] if s2 == 0 else clean[i][a:b] + np.float32(math.sqrt(s2)) * noise[i][a:b]
                        ll = body_loglik(y, sig, s2)
                        for c in range(n_cls):
                            if bounds[c] == bounds[c + 1]:
                                continue
                            seg = ll[:, bounds[c]:bounds[c + 1]]
                            old = top[i, j, half, a:b, c]
                            new = np.maximum(old, seg.max(1))
                            if s2 > 0:
                                e = np.exp(seg - new.astype(np.float32)[:, None]).sum(1, dtype=np.float64)
                                acc[i, j, half, a:b, c] = acc[i, j, half, a:b, c] * np.exp(old - new) + e
                            top[i, j, half, a:b, c] = new
        done, el = first + m, time.time() - t0
        if el - last >= 30 or done == n_prior:
            last = el
            print("  prior %d/%d draws (per class %s), %.0f s, about %.0f s left"
                  % (done, n_prior, "/".join(map(str, counts.sum(0))), el, el * (n_prior - done) / done), flush=True)
    out = {}
    with np.errstate(divide="ignore", invalid="ignore"):  # a class without draws in a half: -inf, never chosen
        for i in range(len(masks)):
            for j, s2 in enumerate(s2s):
                t, s = top[i, j], acc[i, j]
                if s2 == 0:
                    full, half = np.maximum(t[0], t[1]).argmax(1), t[0].argmax(1)
                else:
                    mx = np.maximum(t[0], t[1])
                    full = (mx + np.log(s[0] * np.exp(t[0] - mx) + s[1] * np.exp(t[1] - mx))
                            - np.log(counts.sum(0))).argmax(1)
                    half = (t[0] + np.log(s[0]) - np.log(counts[0])).argmax(1)
                out[(i, s2)] = (full, half)
    return out, counts.sum(0)

def macro_f1(pred, truth, n_cls):
    f1 = []
    for c in range(n_cls):
        tp = np.sum((pred == c) & (truth == c))
        den = np.sum(pred == c) + np.sum(truth == c)
        f1.append(2.0 * tp / den if den else 0.0)
    return float(np.mean(f1))


def write_csv(path, scenario, rows, extra_cols=()):
    """Rows in the columns of sems_eval's exp1_recognition.csv (and extra_cols after them); the
    file's rows of other scenarios or other masks are kept, so one file holds both scenes and
    several runs' masks (apps/figures/plot_results.py draws a bound_<csv> beside its experiment)."""
    cols = ["experiment", "scenario", "method", "mask", "n_pilots", "snr_db", "accuracy", "macro_f1", "n_frames",
            "seed", "train_seed", "us_per_frame", "train_seconds", "model"] + list(extra_cols)
    kept = []
    if os.path.exists(path):
        with open(path, newline="") as f:
            ours = {(r["mask"], method_family(r["method"])) for r in rows}
            kept = [r for r in csv.DictReader(f)
                    if r["scenario"] != scenario or (r["mask"], method_family(r["method"])) not in ours]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(kept + rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mask", action="append", required=True,
                    help="mask file or pattern (doppler, uniform, random, optionally :N pilots; blocks:S,K[,ds[,dm]]); "
                    "repeatable")
    ap.add_argument("--label", action="append", default=[],
                    help="the name of each --mask in the output and the CSV (default: the pattern or file name)")
    ap.add_argument("--bundle", action="append", default=[], help="classifier bundle to score (repeatable)")
    ap.add_argument("--heading", choices=["approaching", "any"],
                    help="the heading of the paper's random scene (default approaching)")
    ap.add_argument("--scene", help="a scene file instead of the paper's scene: one random target with one path "
                    "and a Rayleigh gain, its class library's targets bodies of scatterers (e.g. "
                    "models/scenes/kinematic_any.json); the prior is streamed in chunks")
    ap.add_argument("--snr", default="0,10", help="SNR points (dB), comma-separated; inf = noiseless")
    ap.add_argument("--frames", type=int, default=30000, help="test frames")
    ap.add_argument("--prior", type=int, default=40000, help="prior draws (noiseless frames) per class, about")
    ap.add_argument("--pilots", type=int, default=32, help="N_p of the named patterns")
    ap.add_argument("--seed", type=int, default=20261125, help="test frames' channel seed; the prior's is seed + 1")
    ap.add_argument("--as-decoder", action="store_true",
                    help="name the --csv rows as the decoder this prior size makes ('%s'), never as the bound: "
                    "e.g. --prior 5000 on a scene of six classes is the Bayes classifier that knows only as many "
                    "draws as a network trained on 30 000 frames" % (METHOD_DRAWS % "N"))
    ap.add_argument("--save-mask", help="write the first --mask to this mask file and stop (for sems_train --mask)")
    ap.add_argument("--csv", help="write the Bayes rows to this CSV (sems_eval's experiment-1 columns; the "
                    "scenario is 'default' for the approaching heading, 'any' for any)")
    args = ap.parse_args()
    if args.label and len(args.label) != len(args.mask):
        ap.error("--label: give one per --mask (%d masks, %d labels)" % (len(args.mask), len(args.label)))
    if args.frames < 1 or args.prior < 2:
        ap.error("--frames must be >= 1 and --prior >= 2")
    if args.scene and args.heading:
        ap.error("--heading: the --scene file sets the heading")
    args.heading = args.heading or "approaching"
    from gnuradio import sems

    t0 = time.time()
    fs = sems.frame_settings()
    if args.scene:
        scene, unit = load_scene(sems, args.scene)
        cls_names = [scene.class_name(c) for c in scene.label_classes()]
    else:
        spec = sems.random_spec()
        spec.heading = sems.heading_from_name(args.heading)
        scene = sems.scene.random(spec)
        cls_names = list(sems.class_names())
    masks = [pattern_mask(sems, name, fs, args.pilots) for name in args.mask]
    if args.save_mask:
        masks[0].save(args.save_mask)
        print("wrote", args.save_mask)
        return
    labels = args.label or [os.path.basename(os.path.dirname(n)) if n.endswith("mask.json") else n
                            for n in args.mask]
    bundles = [sems.model_bundle.load(b) for b in args.bundle]
    decs = [sems.bundle_decoder(b, 1) for b in bundles]
    all_masks = masks + [b.mask for b in bundles]
    idx = [np.array(mk.flat_indices()) for mk in all_masks]
    n_cls = len(cls_names)
    if args.scene:
        test, t_cls, t_gain = draw_scene_test(sems, scene, fs, idx, cls_names, args.frames, args.seed)
    else:
        test, t_cls, t_gain = draw(sems, scene, idx, args.frames, args.seed)
        prior, p_cls, _ = draw(sems, scene, idx[:len(masks)], n_cls * args.prior, args.seed + 1)
    # unit complex Gaussian noise on the whole grid, drawn once: every SNR point and every mask
    # sees the same noise on the resource elements it reads
    rng = np.random.default_rng(args.seed + 2)
    shape = (args.frames, fs.n_symbols * fs.n_subcarriers)
    noise = ((rng.standard_normal(shape, dtype=np.float32) + 1j * rng.standard_normal(shape, dtype=np.float32))
             / np.sqrt(2)).astype(np.complex64)
    snrs = [float(s) for s in args.snr.split(",")]
    if args.scene:
        print("classifier_bayes: scene %s (classes %s), %d test frames (seed %d), prior %d draws of the scene "
              "with a unit gain (seed %d), %d SNR points" % (args.scene, ", ".join(cls_names), args.frames, args.seed,
                                                               n_cls * args.prior, args.seed + 1, len(snrs)), flush=True)
        t1 = time.time()
        decisions, per_cls = bayes_scene(sems, unit, fs, idx[:len(masks)], cls_names, test[:len(masks)],
                                         [noise[:, i] for i in idx[:len(masks)]],
                                         [10 ** (-snr / 10) for snr in snrs], n_cls * args.prior, args.seed + 1)
        us_scene = 1e6 * (time.time() - t1) / (args.frames * len(snrs) * len(masks))
        n_prior = int(per_cls.sum())
    else:
        # the signature of each prior draw: pilots / |alpha| (unit modulus)
        sig = [p / np.sqrt(np.mean(np.abs(p) ** 2, axis=1, keepdims=True)) for p in prior]
        per_cls = np.bincount(p_cls, minlength=n_cls)
        n_prior = len(p_cls)
    print("classifier_bayes: %s heading, %d test frames (seed %d), prior %s draws per class (seed %d)"
          % (args.heading if not args.scene else "the scene's", args.frames, args.seed, "/".join(map(str, per_cls)),
             args.seed + 1), flush=True)
    for name, mk in zip(labels, masks):
        print("  mask %s: %d pilots on %d symbols x %d subcarriers" % (
            name, mk.size(), len({n for n, _ in mk.positions()}), len({c for _, c in mk.positions()})))
    names = labels + ["bundle " + b for b in args.bundle]
    print("%6s " % "SNR dB" + "  ".join("%24s" % n[-24:] for n in names)
          + "   (Bayes: accuracy with all / half of the prior draws, ! = not converged, macro-F1)")
    if args.scene:
        scenario = os.path.splitext(os.path.basename(args.scene))[0]
    else:
        scenario = "default" if args.heading == "approaching" else "any"
    rows = []
    for snr in snrs:
        s2 = 10 ** (-snr / 10)  # 0 for inf: noiseless
        cols, extra, right = [], [], []
        for i, clean in enumerate(test):
            y = (clean + math.sqrt(s2) * noise[:, idx[i]]).astype(np.complex64)
            if i < len(masks):
                if args.scene:
                    full, half = decisions[(i, s2)]
                    us = us_scene
                else:
                    t1 = time.time()
                    full, half = bayes_classify(y, sig[i], p_cls, n_cls, s2)
                    us = 1e6 * (time.time() - t1) / len(y)
                acc, acc_h, f1 = np.mean(full == t_cls), np.mean(half == t_cls), macro_f1(full, t_cls, n_cls)
                # Converged: half the draws give the same accuracy within one binomial standard
                # error. Where they do not (high SNR: the likelihood peaks between the draws),
                # the accuracy is a reachable one but below the bound: its CSV row says so.
                converged = abs(acc - acc_h) <= math.sqrt(max(acc * (1 - acc), 1.0 / args.frames) / args.frames)
                cols.append("%.4f / %.4f%s, %.4f" % (acc, acc_h, "" if converged else "!", f1))
                extra.append(by_fade(full, t_cls, t_gain))
                right.append(full == t_cls)
                rows.append(dict(experiment=1, scenario=scenario, mask=labels[i],
                                 method=(METHOD_DRAWS % "{:,}".format(n_prior).replace(",", " ")
                                         if args.as_decoder else METHOD if converged else METHOD_UNCONVERGED),
                                 n_pilots=masks[i].size(), snr_db="%g" % snr, accuracy="%.6f" % acc,
                                 macro_f1="%.6f" % f1, n_frames=args.frames, seed=args.seed, train_seed="none",
                                 us_per_frame="%.1f" % us, train_seconds=0,
                                 model="classifier_bayes.py, %d prior draws" % n_prior))
                if args.scene:
                    rows[-1].update(accuracy_half="%.6f" % acc_h, converged=int(converged),
                                    prior_per_class="/".join(map(str, per_cls)))
            else:
                dec = decs[i - len(masks)]
                pred = np.concatenate([np.asarray(dec.classify(y[j:j + 256])).argmax(1)
                                       for j in range(0, len(y), 256)])
                cols.append("%.4f, %.4f" % (np.mean(pred == t_cls), macro_f1(pred, t_cls, n_cls)))
                extra.append(by_fade(pred, t_cls, t_gain))
                right.append(pred == t_cls)
        se = math.sqrt(0.25 / args.frames)
        print("%6g " % snr + "  ".join("%24s" % c for c in cols) + "   (1 SE <= %.4f)" % se, flush=True)
        for n, e in zip(names, extra):
            print("         %s: accuracy by |alpha|^2 %s" % (n, e), flush=True)
        if len(right) > 1:
            print("         against %s on the same frames (difference, 2 paired SE): " % names[0]
                  + "; ".join("%s %s" % (n, paired(r, right[0])) for n, r in zip(names[1:], right[1:])), flush=True)
    if args.scene:
        print("summary: the Bayes accuracy per SNR (all / half of the prior draws; converged = within one SE)")
        for r in rows:
            print("  %-10s %6s dB  %.4f / %.4f  %s" % (r["mask"], r["snr_db"], float(r["accuracy"]),
                                                       float(r["accuracy_half"]),
                                                       "converged" if r["converged"] else "not converged"))
    if args.csv:
        write_csv(args.csv, scenario, rows, ("accuracy_half", "converged", "prior_per_class") if args.scene else ())
        print("wrote", args.csv)
    print("classifier_bayes: done in %.0f s" % (time.time() - t0))


def paired(a, b):
    """Accuracy of a minus that of b on the same frames, with two standard errors of the paired
    difference (from the frames one gets right and the other wrong)."""
    d = a.astype(float) - b.astype(float)
    return "%+.4f ± %.4f" % (d.mean(), 2 * d.std() / math.sqrt(len(d)))


def by_fade(pred, truth, gain):
    out = []
    for lo, hi in BINS:
        s = (gain >= lo) & (gain < hi)
        out.append("[%g, %g) %.3f" % (lo, hi, np.mean(pred[s] == truth[s]) if s.any() else float("nan")))
    return ", ".join(out)


if __name__ == "__main__":
    main()
