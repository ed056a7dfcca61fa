#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures and tables of experiment 7 (targets of moving scatterers) from sems_eval's CSVs.

    plot_kinematic.py RESULTS [--out DIR] [--tables FILE]

Reads RESULTS/exp7_kinematic.csv (with the 32-pilot Doppler pattern's rows of
bound_kinematic.csv beside it when present: the Monte-Carlo Bayes classifier of
docs/results/classifier_bayes.py --scene), exp7_confusion.csv, exp7_pilot_budget.csv and
exp7_pilot_power.csv (SemS with learned pilot energies), exp7_burst.csv (the burst pattern,
beside the sweep's hand patterns) and exp7_bank.csv (SemS and the Doppler pattern's decoder,
each with a template bank); writes
exp7_kinematic.png (accuracy and macro-F1 against SNR), exp7_confusion.png (the learned mask's
and the best hand pattern's confusion at the confusion SNR, summed over training seeds) and
exp7_pilot_budget.png (accuracy against N_p), and with --tables the markdown tables.

The tables' comparisons (the learned mask against the best hand pattern, overall and by pilot
budget; learned against equal pilot energies; the two decoders with template banks) are paired
tests on the per-frame predictions sems_eval keeps beside these CSVs (<csv stem>_predictions.npz,
exp7_truth.npz): a two-level bootstrap over training seeds and test frames and Holm's correction
over each family, which every table names (apps/figures/claims.py, paired_stats.py). A table
whose kept file is missing names it and the command that writes it.
"""
import argparse
import csv
import math
import os
import sys
from collections import OrderedDict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_results as pr  # noqa: E402  (one set of styles, statistics and table helpers)
import claims  # noqa: E402  (the paired tables)

plt = pr.plt
np = pr.np


ENERGIES = "SemS (learned energies)"
BANK_LEARNED, BANK_DOPPLER = "SemS + template bank", "SemS decoder + template bank (doppler pilots)"


def bound_rows(results):
    """The Bayes classifier's rows for the 32-pilot Doppler pattern (classifier_bayes.py
    --scene writes them for any mask and scene name), as rows of experiment 7's scene."""
    rows = pr.read_csv(os.path.join(results, "bound_kinematic.csv")) or []
    return [dict(r, experiment="7", scenario="kinematic") for r in rows
            if r["mask"] == "doppler" and int(pr.fnum(r["n_pilots"])) == 32]


def save(fig, out, name, rect=None):
    fig.tight_layout(rect=rect)
    path = os.path.join(out, name)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def accuracy_figure(rows, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.6), squeeze=False)
    pr.plot_accuracy(rows, "kinematic", axes[0], "Moving scatterers, any heading")
    # Thirteen methods and the Bayes rows: the legend goes under the panels, not over the
    # lines, and above the footer.
    legend = axes[0][0].get_legend()
    handles, labels = legend.legend_handles if hasattr(legend, "legend_handles") else legend.legendHandles, \
        [t.get_text() for t in legend.get_texts()]
    legend.remove()
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.03), ncol=4, fontsize=7, frameon=False)
    pr.footer(fig, rows)
    return save(fig, out, "exp7_kinematic.png", rect=(0, 0.2, 1, 1))


def best_hand(rows, snr):
    """The hand pattern (method name) with the highest mean accuracy at snr."""
    means = OrderedDict()
    for r in rows:
        if r["method"].startswith("SemS decoder (") and pr.fnum(r["snr_db"]) == snr:
            means.setdefault(r["method"], []).append(pr.fnum(r["accuracy"]))
    return max(means, key=lambda m: sum(means[m]) / len(means[m])) if means else None


def confusion_figure(conf, rows, out):
    snr = pr.fnum(conf[0]["snr_db"])
    hand = best_hand(rows, snr)
    methods = [m for m in ("SemS", hand) if m and any(r["method"] == m for r in conf)]
    classes = list(OrderedDict.fromkeys(r["true_class"] for r in conf))
    fig, axes = plt.subplots(1, len(methods), figsize=(5.2 * len(methods), 4.6), squeeze=False)
    for ax, m in zip(axes[0], methods):
        mat = np.zeros((len(classes), len(classes)))
        for r in conf:
            if r["method"] == m:
                mat[classes.index(r["true_class"]), classes.index(r["predicted_class"])] += int(r["count"])
        frac = mat / np.maximum(mat.sum(axis=1, keepdims=True), 1)
        ax.imshow(frac, cmap="Blues", vmin=0, vmax=1)
        for i in range(len(classes)):
            for j in range(len(classes)):
                ax.text(j, i, "%.2f" % frac[i, j], ha="center", va="center", fontsize=8,
                        color="white" if frac[i, j] > 0.6 else "black")
        ax.set_xticks(range(len(classes)))
        ax.set_xticklabels(classes, rotation=35, ha="right", fontsize=8)
        ax.set_yticks(range(len(classes)))
        ax.set_yticklabels(classes, fontsize=8)
        ax.set_xlabel("predicted")
        ax.set_ylabel("true")
        seeds = len({r["train_seed"] for r in conf if r["method"] == m})
        ax.set_title("%s at %g dB\n(rows: share of each true class; %d seed%s summed)" % (
            "SemS (learned pilots)" if m == "SemS" else m, snr, seeds, "" if seeds == 1 else "s"), fontsize=9)
    return save(fig, out, "exp7_confusion.png")


def budget_rows(rows, budget):
    """The pilot budget sweep's rows with the main part's N_p = 32 rows of the same methods."""
    methods = {r["method"] for r in budget}
    return budget + [r for r in rows if r["method"] in methods]


def budget_figure(rows, out, snrs=(0.0, 10.0, 30.0)):
    fig, axes = plt.subplots(1, len(snrs), figsize=(4.2 * len(snrs), 4.0), squeeze=False)
    for ax, snr in zip(axes[0], snrs):
        rs = [r for r in rows if pr.fnum(r["snr_db"]) == snr]
        lines = pr.series(rs, ["method", "mask"], x="n_pilots")
        names = pr.labels(rs)
        shift = {k: 0.03 * (i - (len(lines) - 1) / 2) for i, k in enumerate(lines)}
        handles = []
        for k, (xs, means, los, his, counts) in lines.items():
            xs = [x * 2 ** shift[k] for x in xs]  # dodge on the log axis
            handles.append(pr.draw(ax, xs, means, los, his, counts, names[k], **pr.style(*k)))
        ax.set_xscale("log", base=2)
        ax.set_xlabel("pilots N_p")
        ax.set_ylabel("accuracy")
        ax.grid(alpha=0.3)
        ax.set_title("%g dB" % snr, fontsize=10)
    axes[0][0].legend(handles=handles, fontsize=7, loc="lower right")
    pr.footer(fig, rows)
    return save(fig, out, "exp7_pilot_budget.png")


def means_by_budget(budget, keep):
    """{N_p: the accuracy at every SNR (mean ± half-range over the seeds) of the methods `keep`
    selects, where it selects more than one}: what a part shows when its predictions were not kept,
    so no paired test."""
    out = OrderedDict()
    for n in sorted({int(pr.fnum(r["n_pilots"])) for r in budget}):
        rs = [r for r in budget if int(pr.fnum(r["n_pilots"])) == n and keep(r["method"])]
        if len({r["method"] for r in rs}) > 1:
            out[n] = pr.pivot(rs, "method", "accuracy")
    return out


def by_budget(tables, text, note="", means=None):
    """Markdown: the text, then one "#### N_p = n" section per table of {N_p: table}; or the note
    of a missing kept file ({None: note}) with the untested accuracies of `means` ({N_p: table})."""
    if None in tables:
        out = [tables[None], ""]
        if means:
            out += ["Accuracy only, not tested (means ± half-range over the seeds; a difference of means "
                    "here is not a paired test):", ""]
            for n, t in means.items():
                out += ["#### N_p = %d" % n, "", t, ""]
        return out
    out = [text, ""] if text else []
    for n, t in tables.items():
        out += ["#### N_p = %d" % n, "", t, ""]
    return out + ([note, ""] if note else [])


def bank_tables(bank, paired):
    """Markdown: per N_p of the bank part, both decoders' accuracy and the learned mask against
    the Doppler pattern when each decoder keeps its training frames (paired)."""
    out = ["### Experiment 7: with template banks, the learned mask against the Doppler pattern", ""]
    tables = paired["bank"]
    if None in tables:
        out += [tables[None], ""]
    elif paired.get("bank_text"):
        out += [paired["bank_text"], ""]
    for n in sorted({int(pr.fnum(r["n_pilots"])) for r in bank}):
        rs = [r for r in bank if int(pr.fnum(r["n_pilots"])) == n]
        out += ["#### N_p = %d" % n, "", pr.pivot(rs, "method", "accuracy"), ""]
        if tables.get(n):
            out += [tables[n], ""]
    return out


def tables(rows, conf, budget, bank=(), paired=None):
    """The markdown tables; paired: claims.exp7_tables() of the results folder."""
    n = pr.n_seeds(rows)
    out = []
    if n > 1:
        out += ["Learned methods: mean ± half-range (max − min) / 2 over %d training seeds on the same test "
                "frames; methods without training: single values." % n, ""]
    out += ["### Experiment 7: accuracy", "", pr.pivot(rows, "method", "accuracy"), "",
            "### Experiment 7: macro-F1", "", pr.pivot(rows, "method", "macro_f1"), ""]
    hand = paired["hand"]
    out += ["### Experiment 7: the learned mask against the best hand pattern", ""]
    out += [paired["hand_text"], "", hand[32], ""] if hand.get(32) else [
        hand.get(None) or "*No paired test at N_p = 32 in the kept predictions.*", ""]
    if conf:
        snr = pr.fnum(conf[0]["snr_db"])
        classes = list(OrderedDict.fromkeys(r["true_class"] for r in conf))
        for m in OrderedDict.fromkeys(r["method"] for r in conf):
            mat = OrderedDict(((t, p), 0) for t in classes for p in classes)
            for r in conf:
                if r["method"] == m:
                    mat[(r["true_class"], r["predicted_class"])] += int(r["count"])
            out += ["### Experiment 7: confusion of %s at %g dB (counts summed over seeds; rows true, "
                    "columns predicted)" % (m, snr), "",
                    "| true \\ predicted | %s |" % " | ".join(classes), "|" + "---|" * (len(classes) + 1)]
            for t in classes:
                out.append("| %s | %s |" % (t, " | ".join(str(mat[(t, p)]) for p in classes)))
            out.append("")
    if budget:
        # One table, a column per SNR of the figure's panels.
        out += ["### Experiment 7: accuracy by pilot budget", ""]
        rs = [dict(r, method="%s, N_p %s" % (r["method"], r["n_pilots"]))
              for r in budget if pr.fnum(r["snr_db"]) in (0.0, 10.0, 30.0)]
        rs.sort(key=lambda r: (r["method"].split(", N_p")[0], int(pr.fnum(r["n_pilots"]))))
        out += [pr.pivot(rs, "method", "accuracy"), ""]
        out += ["### Experiment 7: the learned mask against the best hand pattern by pilot budget", ""]
        out += by_budget(hand, paired.get("hand_text"), paired.get("hand_note", ""),
                         means_by_budget(budget, lambda m: m == "SemS" or claims.hand_pattern(m)))
        if any(r["method"] == ENERGIES for r in budget):
            out += ["### Experiment 7: learned pilot energies against equal energies (the same learner)", ""]
            out += by_budget(paired["energies"], paired.get("energies_text"), "",
                             means_by_budget(budget, lambda m: m in ("SemS", ENERGIES)))
    if bank:
        out += bank_tables(bank, paired)
    return "\n".join(out)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="directory with experiment 7's CSVs")
    ap.add_argument("--out", help="where to write the PNGs (default: the results directory)")
    ap.add_argument("--tables", help="also write the tables as markdown to this file")
    ap.add_argument("--bootstrap", type=int, default=claims.BOOTSTRAP,
                    help="bootstrap resamples of the paired tables (default %d)" % claims.BOOTSTRAP)
    a = ap.parse_args(argv)
    if a.bootstrap < 100:
        print("plot_kinematic: --bootstrap must be >= 100, got %d" % a.bootstrap, file=sys.stderr)
        return 2
    rows = pr.read_csv(os.path.join(a.results, "exp7_kinematic.csv"))
    if not rows:
        print("plot_kinematic: no exp7_kinematic.csv in %s" % a.results, file=sys.stderr)
        return 1
    conf = pr.read_csv(os.path.join(a.results, "exp7_confusion.csv")) or []
    power = pr.read_csv(os.path.join(a.results, "exp7_pilot_power.csv")) or []
    burst = pr.read_csv(os.path.join(a.results, "exp7_burst.csv")) or []  # a hand pattern beside the sweep's
    budget = (pr.read_csv(os.path.join(a.results, "exp7_pilot_budget.csv")) or []) + burst + power
    budget = budget_rows(rows, budget) if budget else []
    bank = pr.read_csv(os.path.join(a.results, "exp7_bank.csv")) or []
    rows += [r for r in power if int(pr.fnum(r["n_pilots"])) == 32]  # beside every method at 32 pilots
    rows += bound_rows(a.results)
    out = a.out or a.results
    os.makedirs(out, exist_ok=True)
    made = [accuracy_figure(rows, out)]
    if conf:
        made.append(confusion_figure(conf, rows, out))
    if budget:
        made.append(budget_figure(budget, out))
    for p in made:
        print("wrote", p)
    if a.tables:
        paired = claims.exp7_tables(a.results, a.bootstrap)
        for part in ("hand", "energies", "bank"):
            if None in paired[part]:
                print("plot_kinematic: %s" % paired[part][None], file=sys.stderr)
        with open(a.tables, "w") as f:
            f.write(tables(rows, conf, budget, bank, paired))
        print("wrote", a.tables)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
