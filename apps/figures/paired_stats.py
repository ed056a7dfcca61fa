#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The paired statistics of the evaluation's tables: one module for every experiment.

Two methods scored on the same test frames are compared through their per-frame scores
(correctness 1/0, or the absolute delay-index error), not through their means alone: the
frames are shared, so most of the noise of one mean is the noise of the other.

  two_level(a, b, rng)      mean difference of a and b (arrays training seed x test frame),
                            its standard error from a two-level paired bootstrap (training
                            seeds resampled with replacement, and test frames with replacement,
                            the same frame indices for both methods and every seed), and its
                            two-sided p-value
  one_level(d, rng, boots)  the same over one level: per-item differences d (already averaged
                            over seeds), items resampled (apps/figures/plot_tracks.py)
  align(sa, sb)             two methods' {training seed: scores} as arrays for two_level
  normal_p(diff, se)        two-sided p of diff / se under the normal approximation
  holm(pvalues)             Holm's step-down adjusted p-values
  verdict(diff, p_holm)     "ahead", "behind" or "tied" at ALPHA
  Family(name)              the tests that answer one question: Holm over all of them, each
                            test's verdict, and a sentence naming the family and correction

p-values come from the normal approximation (difference over its bootstrap SE), not from the
bootstrap's own tail fraction: with B resamples that fraction cannot resolve a p below 1/B,
and Holm's thresholds over tens of tests (0.05/45 ≈ 0.001) need smaller ones; the mean over
thousands of frames is close to normal.

Two levels because the training seed is a source of variation of its own: a learned method's
accuracy differs from seed to seed on the same frames. Resampling the seeds adds that spread
to the frames' (with S seeds the bootstrap's seed level draws from S values, so with 3 seeds
it has few to draw from: the SE is still an estimate from 3 trainings). A method without
training pairs with every seed of the other. The exact bootstrap variance of the mean
difference, for d = a - b decomposed as d[s, f] = mu + alpha_s + beta_f + gamma_sf (effects
centred), is var(alpha)/S + var(beta)/n + var(gamma)/(S n) (population variances); with one
seed it is var(d)/n.
"""
import math
import zlib

import numpy as np

ALPHA = 0.05


def holm(pvalues):
    """Holm-adjusted p-values (same order)."""
    order = sorted(range(len(pvalues)), key=lambda i: pvalues[i])
    adjusted = [0.0] * len(pvalues)
    running = 0.0
    m = len(pvalues)
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * pvalues[i]))
        adjusted[i] = running
    return adjusted


def normal_p(diff, se):
    """Two-sided p of diff against its standard error (normal approximation); 1 for a zero
    difference without spread, 0 for a non-zero one."""
    if se > 0:
        return math.erfc(abs(diff) / se / math.sqrt(2.0))
    return 1.0 if diff == 0 else 0.0


def one_level(d, rng, boots):
    """Mean of per-item differences d, its bootstrap SE over items (boots resamples) and p."""
    d = np.asarray(d, dtype=float)
    n = len(d)
    idx = rng.integers(0, n, size=(boots, n))
    means = d[idx].mean(axis=1)
    se = float(means.std(ddof=1))
    diff = float(d.mean())
    return {"diff": diff, "se": se, "p": normal_p(diff, se), "n": n}


def two_level(a, b, rng, boots=2000, paired_seeds=True):
    """Mean difference a - b over training seeds and test frames, its two-level paired
    bootstrap SE and two-sided p.

    a, b: arrays (seeds x frames, or one row) of per-frame scores on the same frames. With
    paired_seeds their rows are the same training seeds (row s of a with row s of b, as align()
    gives them) and the seeds are resampled once for both; otherwise each method's seeds are
    resampled on their own. The frames are resampled once per resample for both methods and
    every seed."""
    a = np.atleast_2d(np.asarray(a, dtype=float))
    b = np.atleast_2d(np.asarray(b, dtype=float))
    n = a.shape[1]
    if b.shape[1] != n or n == 0:
        raise ValueError("two_level: both methods need the same test frames (%d and %d)" % (n, b.shape[1]))
    if paired_seeds and a.shape[0] != b.shape[0]:
        raise ValueError("two_level: paired seeds need as many rows in a (%d) as in b (%d)" % (a.shape[0], b.shape[0]))
    diff = float(a.mean() - b.mean())
    parts = [a - b] if paired_seeds else [a, -b]
    rows = sum(p.shape[0] for p in parts)
    means = np.zeros(boots)
    chunk = max(1, min(boots, 4_000_000 // (n * rows)))  # a few tens of MB per step
    for start in range(0, boots, chunk):
        k = min(chunk, boots - start)
        frames = rng.integers(0, n, size=(k, n))
        for p in parts:
            per_seed = p[:, frames].mean(axis=2).T  # resample x seed: each seed's mean over the drawn frames
            seeds = rng.integers(0, p.shape[0], size=(k, p.shape[0]))
            means[start:start + k] += np.take_along_axis(per_seed, seeds, axis=1).mean(axis=1)
    se = float(means.std(ddof=1)) if boots > 1 else 0.0
    # Identical resamples: rounding, not spread. Against the scores' own scale, so that scores in
    # small units (squared errors in rad², 1e-6) keep the spread of their rounding-sized differences.
    scale = max(float(np.abs(a).max()), float(np.abs(b).max()), abs(diff))
    if se < 1e-12 * scale:
        se = 0.0
    return {"diff": diff, "se": se, "p": normal_p(diff, se), "n": n,
            "seeds": a.shape[0] if paired_seeds else (a.shape[0], b.shape[0]),
            "a": float(a.mean()), "b": float(b.mean())}


def align(sa, sb):
    """Two methods' {training seed: per-frame scores} as (a, b, paired_seeds) for two_level.
    Seeds both have are paired, row by row; a method without training (its one key None)
    pairs with every seed of the other; methods with disjoint seeds are resampled each on its
    own. None when either is empty."""
    if not sa or not sb:
        return None
    if None in sa and None in sb:
        return np.array([sa[None]]), np.array([sb[None]]), True
    if None in sa or None in sb:
        seeds = sorted(sb if None in sa else sa)
        return (np.array([sa.get(s, sa.get(None)) for s in seeds]),
                np.array([sb.get(s, sb.get(None)) for s in seeds]), True)
    shared = sorted(set(sa) & set(sb))
    if shared:
        return np.array([sa[s] for s in shared]), np.array([sb[s] for s in shared]), True
    return np.array([sa[s] for s in sorted(sa)]), np.array([sb[s] for s in sorted(sb)]), False


def compare(sa, sb, rng, boots=2000):
    """two_level on align(sa, sb); None when either method has no scores."""
    al = align(sa, sb)
    return None if al is None else two_level(al[0], al[1], rng, boots, paired_seeds=al[2])


def rng_for(seed, key):
    """A generator of its own for one comparison, from the run's seed and the comparison's key,
    so that a comparison's resamples do not depend on which others are made before it."""
    return np.random.default_rng([seed, zlib.crc32(repr(key).encode("utf-8"))])


def verdict(diff, p_adjusted, lower_is_better=False, alpha=ALPHA):
    """'ahead' (the first method better), 'behind' or 'tied' (no difference that survives the
    correction): from a Holm-adjusted p at level alpha."""
    if p_adjusted >= alpha:
        return "tied"
    better = diff < 0 if lower_is_better else diff > 0
    return "ahead" if better else "behind"


class Family:
    """The tests that answer one question. Holm's correction runs over every test added;
    results() gives each test with its adjusted p and verdict, describe() names the family,
    its size and the correction."""

    def __init__(self, name, lower_is_better=False, alpha=ALPHA):
        self.name, self.lower_is_better, self.alpha = name, lower_is_better, alpha
        self.tests = []

    def add(self, key, result):
        if result is not None:
            self.tests.append((key, result))
        return result

    def __len__(self):
        return len(self.tests)

    def results(self):
        """[(key, result, Holm-adjusted p, verdict)] in the order added."""
        adjusted = holm([r["p"] for _, r in self.tests])
        return [(k, r, a, verdict(r["diff"], a, self.lower_is_better, self.alpha))
                for (k, r), a in zip(self.tests, adjusted)]

    def describe(self):
        return ("family \"%s\": %d test%s, Holm's step-down correction over all of them at α = %g" % (
            self.name, len(self), "" if len(self) == 1 else "s", self.alpha))
