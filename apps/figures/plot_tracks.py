#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Experiment 8's figures, tables and paired statistics (decisions over a track).

    plot_tracks.py RESULTS [--tables FILE] [--bootstrap B] [--seed S]

Reads RESULTS/exp8_tracks.csv (scores), exp8_predictions.csv (every method's decision on every
test track) and exp8_truth.csv (the test tracks' classes and lengths), written by
`sems_eval --experiments 8` (scripts/evaluation/eval_tracks.sh), and writes

  RESULTS/exp8_tracks.png        accuracy against observation time, one panel per SNR, N_p = 32
                                 (mean over training seeds; the band spans the seeds)
  RESULTS/exp8_pilot_budget.png  accuracy over the longest observation time against N_p
  --tables FILE                  the tables (markdown): accuracy by observation time and SNR,
                                 macro-F1, the time each method needs to reach 90 % and 95 % of
                                 its accuracy over the longest time, the paired comparisons of
                                 SemS-track with each reference, and the adult/child pair.

Paired statistics (apps/figures/paired_stats.py, shared with the other experiments' tables):
for two methods on the same test tracks, a track's difference is its correctness under one minus
under the other, averaged over the training seeds both share; the mean difference's standard
error comes from a bootstrap over test tracks, and its two-sided p-value from the difference
over that standard error (normal approximation).
Every comparison that covers several SNRs and observation times is one family, and its p-values
get Holm's correction: a cell is "better" or "worse" only if it survives at level 0.05.
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired_stats  # noqa: E402  (Holm, the bootstrap and the verdicts of every experiment's tables)
from paired_stats import ALPHA, holm  # noqa: E402,F401  (holm: this module's name for it, as before)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SEMS = "SemS-track"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class predictions:
    """Per-track decisions: (method, N_p, SNR, frames) -> {train seed: int array, -1 = too short}."""

    def __init__(self, rows, truth):
        self.truth = np.array([int(r["class_id"]) for r in truth])
        self.length = np.array([int(r["frames"]) for r in truth])
        self.by = defaultdict(dict)
        for r in rows:
            key = (r["method"], int(r["n_pilots"]), float(r["snr_db"]), int(r["frames"]))
            self.by[key][r["train_seed"]] = np.array([int(v) for v in r["predicted"].split()])

    def correct(self, method, np_, snr, frames):
        """Seed -> 0/1 correctness of the tracks that last `frames` frames (and that mask)."""
        seeds = self.by.get((method, np_, snr, frames))
        if not seeds:
            return None, None
        keep = self.length >= frames
        return {s: (p[keep] == self.truth[keep]).astype(float) for s, p in seeds.items()}, keep

    def paired(self, a, b, np_a, np_b, snr, frames, rng, boots):
        """Mean accuracy difference a - b over the shared seeds, its bootstrap SE and p (two-sided),
        and each method's accuracy on those seeds (what the difference is the difference of)."""
        ca, _ = self.correct(a, np_a, snr, frames)
        cb, _ = self.correct(b, np_b, snr, frames)
        if ca is None or cb is None:
            return None
        # A method without training ("none") pairs with every seed of the other.
        sa = set(ca) if "none" not in ca else set(cb)
        sb = set(cb) if "none" not in cb else set(ca)
        seeds = sorted(sa & sb)
        if not seeds:
            return None
        da = np.mean([ca.get(s, ca.get("none")) for s in seeds], axis=0)
        db = np.mean([cb.get(s, cb.get("none")) for s in seeds], axis=0)
        d = da - db
        # The bootstrap over tracks of the seed-averaged differences; two-sided p of the mean
        # difference against its SE (normal approximation: the bootstrap's own tail fractions
        # cannot resolve the small p-values Holm needs).
        r = paired_stats.one_level(d, rng, boots)
        return {"diff": r["diff"], "se": r["se"], "p": r["p"], "tracks": r["n"], "seeds": len(seeds),
                "a": float(np.mean(da)), "b": float(np.mean(db))}


def verdict(r, adjusted):
    """'+' better, '−' worse, '=' no difference that survives the correction (adjusted p)."""
    return {"ahead": "+", "behind": "−", "tied": "="}[paired_stats.verdict(r["diff"], adjusted)]


def mean_over_seeds(rows, key):
    """(method, N_p, SNR, frames) -> (mean, min, max, seeds) of column `key`."""
    acc = defaultdict(list)
    for r in rows:
        acc[(r["method"], int(r["n_pilots"]), float(r["snr_db"]), int(r["frames"]))].append(float(r[key]))
    return {k: (float(np.mean(v)), min(v), max(v), len(v)) for k, v in acc.items()}


def save_grid(fig, axes, panels, entries, path, top=1.0):
    """A grid of panels: unused ones hidden, accuracy on the left column, one legend (from the
    first panel) below in three columns, written to `path`."""
    for ax in axes.flat[panels:]:
        ax.axis("off")
    for ax in axes[:, 0]:
        ax.set_ylabel("accuracy")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.04 + 0.03 * int(math.ceil(entries / 3)), 1, top))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def method_order(methods):
    first = [SEMS, "SemS fusion"]
    rest = sorted(m for m in methods if m not in first)
    key = lambda m: (0 if "+ track" in m else 1 if "fusion" in m else 2, m)  # noqa: E731
    return [m for m in first if m in methods] + sorted(rest, key=key)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", help="folder with exp8_tracks.csv, exp8_predictions.csv and exp8_truth.csv")
    ap.add_argument("--tables", default=None, help="markdown tables go here (default RESULTS/track_tables.md)")
    ap.add_argument("--bootstrap", type=int, default=2000, help="bootstrap resamples (default 2000)")
    ap.add_argument("--seed", type=int, default=8, help="seed of the bootstrap")
    ap.add_argument("--frame-ms", type=float, default=32.0, help="one frame's duration in ms (N x T; default 32)")
    ap.add_argument("--script", default="scripts/evaluation/eval_tracks.sh",
                    help="the script that ran the experiment, named in the tables (default the paper frame's)")
    args = ap.parse_args()
    if args.bootstrap < 100:
        raise SystemExit("plot_tracks.py: --bootstrap must be >= 100, got %d" % args.bootstrap)
    rows = read_csv(os.path.join(args.results, "exp8_tracks.csv"))
    if not rows:
        raise SystemExit("plot_tracks.py: %s/exp8_tracks.csv has no rows" % args.results)
    pred = predictions(read_csv(os.path.join(args.results, "exp8_predictions.csv")),
                       read_csv(os.path.join(args.results, "exp8_truth.csv")))
    class_names = {int(r["class_id"]): r["class"] for r in read_csv(os.path.join(args.results, "exp8_truth.csv"))}
    tables = args.tables or os.path.join(args.results, "track_tables.md")
    rng = np.random.default_rng(args.seed)
    acc = mean_over_seeds(rows, "accuracy")
    f1 = mean_over_seeds(rows, "macro_f1")
    snrs = sorted({k[2] for k in acc})
    frames = sorted({k[3] for k in acc})
    t_max = frames[-1]
    budgets = sorted({k[1] for k in acc if k[0] == SEMS})
    main_np = 32 if 32 in budgets else budgets[0]
    # Pilots across frames have a section of their own (below), not a place among the references.
    across = lambda m: "super-frame" in m or "across frames" in m  # noqa: E731
    methods = method_order({k[0] for k in acc if (k[1] == main_np or "CNN" in k[0]) and not across(k[0])})
    np_of = {m: (main_np if (m, main_np, snrs[0], frames[0]) in acc else
                 next(k[1] for k in acc if k[0] == m)) for m in methods}
    n_tracks = len(pred.truth)
    seeds = sorted({r["train_seed"] for r in rows if r["method"] == SEMS})
    secs = lambda f: f * args.frame_ms / 1e3  # noqa: E731

    # Figure: accuracy against observation time, one panel per SNR.
    cols = min(3, len(snrs))
    rws = int(math.ceil(len(snrs) / cols))
    fig, axes = plt.subplots(rws, cols, figsize=(5.0 * cols, 3.6 * rws), squeeze=False, sharey=True)
    palette = plt.cm.tab10(np.arange(10)) if len(methods) <= 10 else plt.cm.tab20(np.arange(20))
    colours = dict(zip(methods, palette[np.arange(len(methods)) % len(palette)]))
    for ax, snr in zip(axes.flat, snrs):
        for m in methods:
            pts = [(f, acc[(m, np_of[m], snr, f)]) for f in frames if (m, np_of[m], snr, f) in acc]
            if not pts:
                continue
            t = [secs(f) for f, _ in pts]
            style = "-o" if m == SEMS else ("--" if "fusion" in m else "-")
            ax.plot(t, [v[0] for _, v in pts], style, color=colours[m], ms=3, lw=2 if m == SEMS else 1, label=m)
            ax.fill_between(t, [v[1] for _, v in pts], [v[2] for _, v in pts], color=colours[m], alpha=0.12, lw=0)
        ax.set_xscale("log")
        ticks = [secs(f) for i, f in enumerate(frames) if i % 2 == 0 or f == t_max]
        ax.set_xticks(ticks)
        ax.set_xticklabels(["%.3g" % x for x in ticks])
        ax.minorticks_off()
        ax.set_title("%g dB" % snr)
        ax.set_xlabel("observation time (s)")
        ax.set_ylim(0, 1)
        ax.grid(alpha=0.3)
    fig.suptitle("Decisions over a track, kinematic library, N_p = %d (%d test tracks, %d training seed(s))"
                 % (main_np, n_tracks, len(seeds)), fontsize=10)
    save_grid(fig, axes, len(snrs), len(methods), os.path.join(args.results, "exp8_tracks.png"), top=0.96)

    # Figure: the pilot budget at the longest observation time.
    budget_methods = [m for m in method_order({k[0] for k in acc}) if len({k[1] for k in acc if k[0] == m}) > 1]
    if len(budgets) > 1:
        fig, axes = plt.subplots(rws, cols, figsize=(4.2 * cols, 3.3 * rws), squeeze=False, sharey=True)
        for ax, snr in zip(axes.flat, snrs):
            for m in budget_methods:
                pts = sorted((k[1], v) for k, v in acc.items() if k[0] == m and k[2] == snr and k[3] == t_max)
                if pts:
                    ax.plot([p for p, _ in pts], [v[0] for _, v in pts], "-o" if m == SEMS else "--", ms=3,
                            color=colours.get(m), label=m)
            ax.set_xscale("log", base=2)
            ax.set_title("%g dB, %.3g s" % (snr, secs(t_max)))
            ax.set_xlabel("pilots per frame")
            ax.set_ylim(0, 1)
            ax.grid(alpha=0.3)
        save_grid(fig, axes, len(snrs), len(budget_methods), os.path.join(args.results, "exp8_pilot_budget.png"))

    # The command that makes these tables again, as the tables name it.
    command = os.path.relpath(args.results)
    if args.frame_ms != 32.0:
        command += " --frame-ms %g" % args.frame_ms
    if args.script != ap.get_default("script"):
        command += " --script %s" % args.script
    out = []
    w = out.append
    w("# Experiment 8: decisions over a track\n")
    w("Generated by `/usr/bin/python3 apps/figures/plot_tracks.py %s` from `sems_eval --experiments 8` "
      "(`%s`). %d test tracks of the kinematic library (any heading, Rayleigh gains new every "
      "frame), the same for every method; training seeds %s; a frame is %.3g ms. Accuracy is the mean over "
      "training seeds; a track counts at an observation time if it lasts that long.\n"
      % (command, args.script, n_tracks, ", ".join(seeds), args.frame_ms))
    for snr in snrs:
        w("\n## Accuracy at %g dB, N_p = %d\n" % (snr, main_np))
        w("| method | " + " | ".join("%d (%.3g s)" % (f, secs(f)) for f in frames) + " |")
        w("|---|" + "---:|" * len(frames))
        for m in methods:
            cells = []
            for f in frames:
                v = acc.get((m, np_of[m], snr, f))
                cells.append("%.3f" % v[0] if v else "")
            w("| %s | %s |" % (m, " | ".join(cells)))
    w("\n## Macro-F1 over %.3g s (%d frames), N_p = %d\n" % (secs(t_max), t_max, main_np))
    w("| method | " + " | ".join("%g dB" % s for s in snrs) + " |")
    w("|---|" + "---:|" * len(snrs))
    for m in methods:
        w("| %s | %s |" % (m, " | ".join("%.3f" % f1[(m, np_of[m], s, t_max)][0]
                                          if (m, np_of[m], s, t_max) in f1 else "" for s in snrs)))

    w("\n## Time to 90 %% and 95 %% of the accuracy over %.3g s\n" % secs(t_max))
    w("The shortest observation time scored whose accuracy reaches 90 % (95 %) of the method's own accuracy over "
      "the longest time, in seconds: the speed/accuracy trade in time.\n")
    w("| method | " + " | ".join("%g dB" % s for s in snrs) + " |")
    w("|---|" + "---:|" * len(snrs))
    for m in methods:
        cells = []
        for s in snrs:
            final = acc.get((m, np_of[m], s, t_max))
            if not final:
                cells.append("")
                continue
            reach = []
            for q in (0.90, 0.95):
                hit = next((f for f in frames if (m, np_of[m], s, f) in acc and acc[(m, np_of[m], s, f)][0]
                            >= q * final[0]), t_max)
                reach.append("%.3g" % secs(hit))
            cells.append(" / ".join(reach))
        w("| %s | %s |" % (m, " | ".join(cells)))

    # Paired comparisons: SemS-track against each reference, one Holm family per reference.
    w("\n## SemS-track against each reference, paired\n")
    w("Difference of accuracy (SemS-track minus the reference) on the same test tracks, averaged over the training "
      "seeds both share, ± its bootstrap standard error over tracks (%d resamples). Each table is one family over "
      "every SNR and observation time, its two-sided p-values (difference over SE, normal approximation) "
      "Holm-corrected at %.2g: **+** SemS-track better, **−** worse, **=** no difference that survives the "
      "correction.\n" % (args.bootstrap, ALPHA))
    references = [m for m in methods if m != SEMS]
    for ref in references:
        cells, keys = [], []
        for s in snrs:
            for f in frames:
                r = pred.paired(SEMS, ref, main_np, np_of[ref], s, f, rng, args.bootstrap)
                if r:
                    cells.append(r)
                    keys.append((s, f))
        if not cells:
            continue
        adj = holm([c["p"] for c in cells])
        w("\n### against %s\n" % ref)
        w("| SNR | " + " | ".join("%d fr" % f for f in frames) + " |")
        w("|---|" + "---:|" * len(frames))
        table = {k: (c, a) for k, c, a in zip(keys, cells, adj)}
        wins = losses = 0
        for s in snrs:
            row = []
            for f in frames:
                if (s, f) not in table:
                    row.append("")
                    continue
                c, a = table[(s, f)]
                mark = verdict(c, a)
                wins += mark == "+"
                losses += mark == "−"
                row.append("%+.3f ± %.3f %s" % (c["diff"], c["se"], mark))
            w("| %g dB | %s |" % (s, " | ".join(row)))
        w("\nBetter in %d, worse in %d of %d cells.\n" % (wins, losses, len(cells)))

    # The pilots (the budget and pilots across frames): a page of their own.
    learned = sorted({k[0] for k in acc if "super-frame" in k[0] and "+ track" in k[0]})
    main_out, out = out, []
    w = out.append
    pilots_page = os.path.join(os.path.dirname(tables) or ".", "track_pilots.md")
    w("# Experiment 8: pilots per frame and across frames\n")
    w("Generated by `/usr/bin/python3 apps/figures/plot_tracks.py %s` with [the other tables of experiment 8]"
      "(%s), from the same test tracks and CSVs.\n" % (command, os.path.basename(tables)))

    # The budget: SemS-track against the best hand pattern under the temporal decoder at each N_p.
    if len(budgets) > 1:
        w("\n## Pilot budget: SemS-track against the best hand pattern under the temporal decoder\n")
        w("At each N_p and SNR over %.3g s: the hand pattern (+ track) with the best mean accuracy there, and the "
          "paired difference, Holm-corrected over the whole table; both accuracies are on the training seeds the "
          "two share, the ones the difference pairs.\n" % secs(t_max))
        cells, keys = [], []
        for b in budgets:
            for s in snrs:
                pats = [m for m in sorted({k[0] for k in acc}) if "+ track" in m and not across(m)
                        and "shipped" not in m and (m, b, s, t_max) in acc]
                if not pats:
                    continue
                best = max(pats, key=lambda m: acc[(m, b, s, t_max)][0])
                r = pred.paired(SEMS, best, b, b, s, t_max, rng, args.bootstrap)
                if r:
                    cells.append((best, r))
                    keys.append((b, s))
        adj = holm([r["p"] for _, r in cells])
        w("| N_p | SNR | SemS-track | best pattern + track | difference |")
        w("|---:|---:|---:|---|---:|")
        for (b, s), (best, r), a in zip(keys, cells, adj):
            mark = verdict(r, a)
            w("| %d | %g dB | %.3f | %s %.3f | %+.3f ± %.3f %s |" % (
                b, s, r["a"], best.replace("SemS decoder ", "").replace(" + track", ""), r["b"], r["diff"], r["se"],
                mark))

    # Pilots across frames: each learned super-frame against the best repeated mask under the
    # temporal decoder (SemS-track's learned mask or a hand pattern), and the SemS decoder's mask
    # moved across the band frame by frame against the same mask repeated (fusion of both).
    if learned:
        w("\n## Pilots across frames: learned super-frames against the best repeated mask\n")
        w("At each N_p and SNR over %.3g s: the learned super-frame under the temporal decoder against the best "
          "repeated mask under the same decoder there (SemS-track's learned mask or a hand pattern, whichever has "
          "the best mean accuracy in that cell: a choice in the repeated masks' favour), paired on the shared "
          "test tracks and seeds, Holm-corrected over the whole table; both accuracies are on the shared seeds.\n"
          % secs(t_max))
        cells, keys = [], []
        for m in learned:
            for b in sorted({k[1] for k in acc if k[0] == m}):
                for s in snrs:
                    if (m, b, s, t_max) not in acc:
                        continue
                    reps = [r for r in sorted({k[0] for k in acc}) if (r == SEMS or ("+ track" in r and not across(r)))
                            and "shipped" not in r and (r, b, s, t_max) in acc]
                    if not reps:
                        continue
                    best = max(reps, key=lambda r: acc[(r, b, s, t_max)][0])
                    r = pred.paired(m, best, b, b, s, t_max, rng, args.bootstrap)
                    if r:
                        cells.append((best, r))
                        keys.append((m, b, s))
        adj = holm([r["p"] for _, r in cells])
        w("| super-frame | N_p | SNR | accuracy | best repeated mask + track | difference |")
        w("|---|---:|---:|---:|---|---:|")
        for (m, b, s), (best, r), a in zip(keys, cells, adj):
            mark = verdict(r, a)
            w("| %s | %d | %g dB | %.3f | %s %.3f | %+.3f ± %.3f %s |" % (
                m.replace("SemS super-frame ", "").replace(" + track", ""), b, s, r["a"],
                best.replace("SemS decoder ", "").replace(" + track", ""), r["b"], r["diff"], r["se"], mark))
        shifted = sorted({k[0] for k in acc if "across frames" in k[0]})
        if shifted:
            w("\nThe same frame decoder with its mask moved across the band frame by frame (the target seen at F "
              "places of the band) against its mask repeated, both fused over the frames, over %.3g s; Holm over the "
              "table.\n" % secs(t_max))
            cells, keys = [], []
            for m in shifted:
                for b in sorted({k[1] for k in acc if k[0] == m}):
                    for s in snrs:
                        r = pred.paired(m, "SemS fusion", b, b, s, t_max, rng, args.bootstrap)
                        if r:
                            cells.append(r)
                            keys.append((m, b, s))
            adj = holm([r["p"] for r in cells])
            w("| N_p | SNR | moved across the band | repeated | difference |")
            w("|---:|---:|---:|---:|---:|")
            for (m, b, s), r, a in zip(keys, cells, adj):
                mark = verdict(r, a)
                w("| %d | %g dB | %.3f | %.3f | %+.3f ± %.3f %s |" % (b, s, r["a"], r["b"], r["diff"], r["se"], mark))


    has_pilots = len(budgets) > 1 or bool(learned)
    if has_pilots:
        with open(pilots_page, "w") as f:
            f.write("\n".join(out) + "\n")
    out = main_out
    w = out.append

    # The confusable pairs: the 2 x 2 accuracy among tracks of either class, after the longest time.
    names = {v: k for k, v in class_names.items()}
    pairs = [("adult", "child", "an adult or a child", " The pairwise bound from the walker's observables is in "
              "[walker_pair_bound.md](%s)." % os.path.relpath(os.path.join(ROOT, "docs", "results", "walker_pair_bound.md"),
                                                              args.results)),
             ("quadcopter", "hexacopter", "a quadcopter or a hexacopter", "")]
    for a_name, c_name, either, bound in pairs:
        if a_name not in names or c_name not in names:
            continue
        a_id, c_id = names[a_name], names[c_name]
        w("\n## The %s/%s pair over %.3g s\n" % (a_name, c_name, secs(t_max)))
        w("Among test tracks of %s: the fraction decided as the right one of the two (decisions for another class "
          "count as wrong), and in brackets the same among the tracks decided as one of the two (the pairwise "
          "accuracy), mean over seeds.%s\n" % (either, bound))
        w("| method | " + " | ".join("%g dB" % s for s in snrs) + " |")
        w("|---|" + "---:|" * len(snrs))
        keep = ((pred.truth == a_id) | (pred.truth == c_id)) & (pred.length >= t_max)
        for m in methods:
            cells = []
            for s in snrs:
                seeds_m = pred.by.get((m, np_of[m], s, t_max))
                if not seeds_m or keep.sum() == 0:
                    cells.append("")
                    continue
                both = np.mean([(p[keep] == pred.truth[keep]).mean() for p in seeds_m.values()])
                pair = [(p[k2] == pred.truth[k2]).mean() for p in seeds_m.values()
                        for k2 in [keep & ((p == a_id) | (p == c_id))] if k2.sum()]
                cells.append("%.3f (%s)" % (both, "%.3f" % np.mean(pair) if pair else "–"))
            w("| %s | %s |" % (m, " | ".join(cells)))
    with open(tables, "w") as f:
        f.write("\n".join(out) + "\n")
    print("plot_tracks.py: wrote %s%s, %s/exp8_tracks.png%s" % (
        tables, ", " + pilots_page if has_pilots else "", args.results,
        ", exp8_pilot_budget.png" if len(budgets) > 1 else ""))


if __name__ == "__main__":
    main()
