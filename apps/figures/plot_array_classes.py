#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Experiment 9's classes part: classification per frame with 1, 4 and 8 receive elements
(exp9_classes.csv and its kept predictions, from `sems_eval --experiments 9 --exp9-parts classes`).

    plot_array_classes.py RESULTS [--table FILE] [--bootstrap B] [--seed S]

Writes RESULTS/exp9_classes.png (accuracy against SNR: each element count beamformed as SemS
Classifier Sink does, beamformed at the true azimuth, and one antenna with the array's gain
10·log10 N added to its SNR) and the table FILE (default RESULTS/exp9_classes.md): the mean
accuracy over the classifier bundles (training seeds) per SNR, then the paired tests on the same
test frames (paired_stats.two_level: training seeds and frames resampled), in two families with
Holm's correction over each:
  - what an array gains: N elements against one element, and 8 against 4, at every SNR;
  - the combination against its references: N elements beamformed against the same frames
    beamformed at the true azimuth, and against one antenna at +10·log10 N dB, at every SNR.
With the tracks part (exp9_tracks.csv, exp9_tracks_predictions.csv, exp9_tracks_truth.csv), the figure gets a second
panel (the track bundle's accuracy against SNR after one frame and after the whole track) and the
table its numbers and a third family: N elements against fewer over the whole track, at every
SNR, paired over the same test tracks (paired_stats.one_level: one track bundle, tracks
resampled). Last, the adult/child pair on its own, per frame and over the track.
"""
import argparse
import csv
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired_stats as ps  # noqa: E402
import predictions as kp  # noqa: E402

SCENARIO = "kinematic_array"
PAIR = ("adult", "child")  # the pair the walker's observables bound (docs/results/walker_pair_bound.md)


def beamformed(k):
    return "1 element" if k == 1 else "%d elements, beamformed" % k


def aimed(k):
    return "%d elements, beamformed at the true azimuth" % k


def gained(k):
    return "one antenna at +10 log10 %d dB" % k


def read(path):
    if not os.path.exists(path):
        sys.exit("plot_array_classes.py: %s is missing: `bash scripts/evaluation/eval_arrays.sh` writes it" % path)
    with open(path) as f:
        return list(csv.DictReader(f))


def mean_accuracy(rows, method, snr):
    v = [float(r["accuracy"]) for r in rows if r["method"] == method and float(r["snr_db"]) == snr]
    return float(np.mean(v)) if v else float("nan")


def paired(exp, np_, snrs, pairs, family, boots, seed):
    """Adds to `family` one test per SNR and (first, rival) method pair; returns the rows."""
    for snr in snrs:
        for first, rival in pairs:
            a, b = exp.scores(SCENARIO, first, np_, snr), exp.scores(SCENARIO, rival, np_, snr)
            family.add((snr, first, rival), ps.compare(a, b, ps.rng_for(seed, (snr, first, rival)), boots))
    return family.results()


def table_of(results, title, describe):
    lines = ["", "**%s** (%s)" % (title, describe), "",
             "| SNR (dB) | first | against | difference (points) | SE | p (Holm) | reading |",
             "|---|---|---|---|---|---|---|"]
    for (snr, first, rival), r, p, verdict in results:
        lines.append("| %g | %s | %s | %+.2f | %.2f | %.2g | %s |" % (
            snr, first, rival, 100 * r["diff"], 100 * r["se"], p, verdict))
    return lines


def pair_cells(predicted, truth, a_id, c_id):
    """Among items of either class: the share decided as the right one of the two (other classes count
    as wrong), and the pairwise accuracy among those decided as one of the two; "" without items."""
    keep = (truth == a_id) | (truth == c_id)
    if not keep.any():
        return ""
    both = (predicted[keep] == truth[keep]).mean()
    two = keep & ((predicted == a_id) | (predicted == c_id))
    return "%.3f (%s)" % (both, "%.3f" % (predicted[two] == truth[two]).mean() if two.any() else "–")


def pair_table(exp, rows, counts, snrs, np_, tracks):
    """The adult/child pair per frame (mean over the classifier bundles) and, with the tracks part,
    over the whole track, for each element count."""
    names = exp.truth.classes[SCENARIO]
    if any(n not in names for n in PAIR):
        return []
    a_id, c_id = names.index(PAIR[0]), names.index(PAIR[1])
    truth = exp.truth.frames[SCENARIO]["class_id"]
    lines = ["", "**The %s/%s pair.** Among frames (tracks) of an %s or a %s: the share decided as the right one of "
             "the two (a decision for another class counts as wrong), and in brackets the same among those decided "
             "as one of the two (the pairwise accuracy). Per frame: mean over the classifier bundles." % (
                 PAIR[0], PAIR[1], PAIR[0], PAIR[1]), "",
             "| method | " + " | ".join("%g dB" % s for s in snrs) + " |", "|---|" + "---:|" * len(snrs)]
    for k in counts:
        cells = []
        for s in snrs:
            per_seed = [kept.values(i) for key, (kept, i) in exp.series.items()
                        if key[0] == SCENARIO and key[1] == beamformed(k) and key[3] == np_ and key[4] == s]
            shares = [pair_cells(p, truth, a_id, c_id) for p in per_seed]
            both = np.mean([float(x.split()[0]) for x in shares if x])
            pair = [float(x.split("(")[1].rstrip(")")) for x in shares if x and "–" not in x]
            cells.append("%.3f (%s)" % (both, "%.3f" % np.mean(pair) if pair else "–"))
        lines.append("| %s, per frame | %s |" % (beamformed(k), " | ".join(cells)))
    if tracks:
        rows_t, (decisions, label, length) = tracks
        longest = max(int(r["frames"]) for r in rows_t)
        for k in counts:
            cells = []
            for s in snrs:
                row = [d for d in decisions if d["method"] == beamformed(k) and float(d["snr_db"]) == s
                       and int(d["frames"]) == longest]
                if not row:
                    cells.append("")
                    continue
                predicted = np.array([int(v) for v in row[0]["predicted"].split()])
                long_enough = length >= longest
                cells.append(pair_cells(predicted[long_enough], label[long_enough], a_id, c_id))
            lines.append("| %s, over %d frames | %s |" % (beamformed(k), longest, " | ".join(cells)))
    return lines


def read_tracks(results):
    """The tracks part's rows and per-track decisions, or None when the run had no tracks part."""
    path = os.path.join(results, "exp9_tracks.csv")
    if not os.path.exists(path):
        return None
    rows = read(path)
    decisions = read(os.path.join(results, "exp9_tracks_predictions.csv"))
    truth = read(os.path.join(results, "exp9_tracks_truth.csv"))
    return rows, (decisions, np.array([int(t["class_id"]) for t in truth]), np.array([int(t["frames"]) for t in truth]))


def track_correct(kept, method, snr, frames):
    """Per test track with at least `frames` frames (in track order): 1.0 where it is decided right."""
    decisions, truth, length = kept
    row = [d for d in decisions if d["method"] == method and float(d["snr_db"]) == snr and int(d["frames"]) == frames]
    predicted = np.array([int(v) for v in row[0]["predicted"].split()])
    return (predicted == truth)[length >= frames].astype(float)


def plot_tracks(ax, tracks, counts, colours):
    rows, _ = tracks
    snrs = sorted({float(r["snr_db"]) for r in rows})
    longest = max(int(r["frames"]) for r in rows)
    for i, k in enumerate(counts):
        for frames, style in ((1, ":"), (longest, "-")):
            acc = [float(r["accuracy"]) for s in snrs for r in rows
                   if r["method"] == beamformed(k) and float(r["snr_db"]) == s and int(r["frames"]) == frames]
            ax.plot(snrs, acc, ls=style, marker="o" if style == "-" else None, color=colours[i % len(colours)],
                    label="%s, %s" % (beamformed(k), "1 frame" if frames == 1 else "%d frames" % longest))
    n = max(int(r["tracks"]) for r in rows)
    ax.set_xlabel("SNR per pilot and element (dB)")
    ax.set_ylabel("accuracy of the decision over the track")
    ax.set_title("over a track crossing the line of sight (track bundle, %d test tracks)" % n, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def tracks_tables(tracks, counts, boots, seed):
    rows, decisions = tracks
    snrs = sorted({float(r["snr_db"]) for r in rows})
    times = sorted({int(r["frames"]) for r in rows})
    longest = times[-1]
    lines = ["", "Over a track (the track bundle's decision after 1 and after %d frames; tracks with fewer frames "
             "than an observation time are left out of it):" % longest, "",
             "| SNR (dB) | " + " | ".join("%s, %s" % (beamformed(k), "1 frame" if t == 1 else "%d frames" % t)
                                         for k in counts for t in (1, longest)) + " |",
             "|---|" + "---|" * (2 * len(counts))]
    for s in snrs:
        cells = []
        for k in counts:
            for t in (1, longest):
                acc = [float(r["accuracy"]) for r in rows
                       if r["method"] == beamformed(k) and float(r["snr_db"]) == s and int(r["frames"]) == t]
                cells.append("%.3f" % acc[0] if acc else "")
        lines.append("| %g | %s |" % (s, " | ".join(cells)))
    family = ps.Family("experiment 9: over a track, N elements against fewer, every SNR")
    more = [k for k in counts if k > 1]
    pairs = [(beamformed(k), beamformed(1)) for k in more if 1 in counts]
    pairs += [(beamformed(hi), beamformed(lo)) for lo in more for hi in more if hi > lo]
    for s in snrs:
        for first, rival in pairs:
            d = track_correct(decisions, first, s, longest) - track_correct(decisions, rival, s, longest)
            family.add((s, first, rival), ps.one_level(d, ps.rng_for(seed, ("tracks", s, first, rival)), boots))
    return lines + table_of(family.results(), "Over a track of %d frames: what the array gains" % longest,
                            family.describe())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--table")
    ap.add_argument("--bootstrap", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rows = read(os.path.join(a.results, "exp9_classes.csv"))
    exp = kp.Experiment(a.results, "9")
    try:
        exp.require("exp9_classes")
    except kp.Missing as e:
        sys.exit("plot_array_classes.py: %s" % e)
    counts = sorted({int(r["elements"]) for r in rows})
    snrs = sorted({float(r["snr_db"]) for r in rows})
    np_, frames = int(rows[0]["n_pilots"]), int(rows[0]["frames"])
    seeds = sorted({r["train_seed"] for r in rows})

    tracks = read_tracks(a.results)
    fig, axes = plt.subplots(1, 2 if tracks else 1, figsize=(13.5 if tracks else 7.5, 4.6), squeeze=False)
    ax = axes[0][0]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, k in enumerate(counts):
        c = colours[i % len(colours)]
        ax.plot(snrs, [mean_accuracy(rows, beamformed(k), s) for s in snrs], marker="o", color=c,
                label=beamformed(k) if k > 1 else "1 element (one antenna)")
        if k > 1:
            ax.plot(snrs, [mean_accuracy(rows, aimed(k), s) for s in snrs], ls=":", color=c,
                    label="%d elements, at the true azimuth" % k)
            ax.plot(snrs, [mean_accuracy(rows, gained(k), s) for s in snrs], ls="--", color=c, alpha=0.7,
                    label="one antenna, SNR + %.1f dB" % (10 * np.log10(k)))
    ax.set_xlabel("SNR per pilot and element (dB)")
    ax.set_ylabel("accuracy (mean of %d training seed%s)" % (len(seeds), "" if len(seeds) == 1 else "s"))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("kinematic classes per frame, %d pilots per element, %d test frames per point" % (
        np_, frames), fontsize=10)
    if tracks:
        plot_tracks(axes[0][1], tracks, counts, colours)
    fig.suptitle("Experiment 9: what 1, 4 and 8 elements read", fontsize=11)
    fig.tight_layout()
    png = os.path.join(a.results, "exp9_classes.png")
    fig.savefig(png, dpi=110)

    methods = []
    for k in counts:
        methods.append(beamformed(k))
        if k > 1:
            methods += [aimed(k), gained(k)]
    lines = ["Generated by `/usr/bin/python3 apps/figures/plot_array_classes.py %s` from exp9_classes.csv and "
             "its kept predictions (%d test frames per point; classifier bundles trained with seed%s %s)." % (
                 a.results, frames,
                 "" if len(seeds) == 1 else "s", ", ".join(seeds)),
             "", "| SNR (dB) | " + " | ".join(methods) + " |", "|---|" + "---|" * len(methods)]
    for s in snrs:
        lines.append("| %g | %s |" % (s, " | ".join("%.3f" % mean_accuracy(rows, m, s) for m in methods)))

    more = [k for k in counts if k > 1]
    gain = ps.Family("experiment 9: N elements against fewer, every SNR")
    pairs = [(beamformed(k), beamformed(1)) for k in more if 1 in counts]
    pairs += [(beamformed(hi), beamformed(lo)) for lo in more for hi in more if hi > lo]
    lines += table_of(paired(exp, np_, snrs, pairs, gain, a.bootstrap, a.seed), "What the array gains",
                      gain.describe())
    refs = ps.Family("experiment 9: the combination against its references, every SNR")
    pairs = [(beamformed(k), aimed(k)) for k in more] + [(beamformed(k), gained(k)) for k in more if 1 in counts]
    lines += table_of(paired(exp, np_, snrs, pairs, refs, a.bootstrap, a.seed),
                      "The combination against its references", refs.describe())
    if tracks:
        lines += tracks_tables(tracks, counts, a.bootstrap, a.seed)
    lines += pair_table(exp, rows, counts, snrs, np_, tracks)
    table = a.table or os.path.join(a.results, "exp9_classes.md")
    with open(table, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("plot_array_classes.py: wrote %s and %s" % (png, table))


if __name__ == "__main__":
    main()
