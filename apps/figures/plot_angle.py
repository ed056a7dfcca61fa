#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Experiment 9's angle part: an array's azimuth estimates against SNR (exp9_angle.csv from
`sems_eval --experiments 9 --exp9-parts angle`, as scripts/evaluation/eval_arrays.sh runs it).

    plot_angle.py RESULTS [--table FILE]

Writes RESULTS/exp9_angle.png (left: one target's RMSE against SNR for each method next to
the Cramér–Rao bound; right: how often both of two coherent targets 1.5 beamwidths apart are
found) and the table FILE (default RESULTS/exp9_angle.md). A "both found" rate is a share of n
frames: its standard error sqrt(p(1 - p)/n) is given in the table and drawn as a band. An RMSE
over n frames has a relative standard error of about 1/sqrt(2n) for Gaussian errors (more with
outliers, which a threshold region has).

With the learned position decoder in the run (`sems_eval --exp9-position-bundle`, one bundle or
several, one per training seed: their RMSE pooled over the seeds, the tests then resampling seeds
and frames), its one-target
estimates are compared frame by frame with each classical method's on the same frames and noise
(exp9_angle_predictions.csv): the mean difference of the squared errors, its bootstrap standard
error over the frames, and Holm's correction over every SNR and method (paired_stats.py). The
predictions are packed into RESULTS/exp9_angle_predictions.npz (each method's estimates, the
truth and each frame's bound, per SNR), which the table is then made from; the CSV may go.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired_stats  # noqa: E402

LEARNED = "SemS position (learned)"
CLASSICAL = ("beamforming", "Capon", "MUSIC")


def predictions(results):
    """{method: (snrs x frames) estimates}, truth (snrs x frames), snrs, from the npz (packed
    from the CSV when the CSV is newer or the npz is missing); None without either."""
    csv_path = os.path.join(results, "exp9_angle_predictions.csv")
    npz_path = os.path.join(results, "exp9_angle_predictions.npz")
    if os.path.exists(csv_path) and (not os.path.exists(npz_path) or
                                     os.path.getmtime(csv_path) > os.path.getmtime(npz_path)):
        rows = read(csv_path)
        snrs = sorted({float(r["snr_db"]) for r in rows})
        frames = 1 + max(int(r["frame"]) for r in rows)
        methods = list(dict.fromkeys(r["method"] for r in rows))
        est = {m: np.full((len(snrs), frames), np.nan) for m in methods}
        truth = np.full((len(snrs), frames), np.nan)
        crb = np.full((len(snrs), frames), np.nan)
        for r in rows:
            i, f = snrs.index(float(r["snr_db"])), int(r["frame"])
            est[r["method"]][i, f] = float(r["azimuth_rad"])
            truth[i, f], crb[i, f] = float(r["truth_rad"]), float(r["crb_rad"])
        np.savez_compressed(npz_path, snr_db=np.array(snrs), truth_rad=truth, crb_rad=crb,
                            methods=np.array(methods), **{"est_%d" % k: est[m] for k, m in enumerate(methods)})
    if not os.path.exists(npz_path):
        return None
    z = np.load(npz_path)
    methods = [str(m) for m in z["methods"]]
    return {m: z["est_%d" % k] for k, m in enumerate(methods)}, z["truth_rad"], [float(s) for s in z["snr_db"]]


def paired_table(results):
    """The learned decoder against each classical method, frame by frame (squared errors)."""
    got = predictions(results)
    if got is None or not any(base(m) == LEARNED for m in got[0]):
        return []
    est, truth, snrs = got
    seeds = [m for m in est if base(m) == LEARNED]  # one learned method per training seed
    family = paired_stats.Family("exp9 learned azimuth against each classical method", lower_is_better=True)
    for i, s in enumerate(snrs):
        for m in CLASSICAL:
            classical = (est[m][i] - truth[i]) ** 2
            if len(seeds) == 1:
                d = (est[LEARNED][i] - truth[i]) ** 2 - classical
                family.add((s, m), paired_stats.one_level(d, paired_stats.rng_for(9, (s, m)), 2000))
            else:  # training seeds and frames resampled; the classical method pairs with every seed
                learned = {l: (est[l][i] - truth[i]) ** 2 for l in seeds}
                family.add((s, m), paired_stats.compare(learned, {None: classical}, paired_stats.rng_for(9, (s, m))))
    res = {k: (r, adj, v) for k, r, adj, v in family.results()}
    lines = ["", "Paired, on the same frames: the learned decoder's squared azimuth error minus each method's, "
             "mean ± 2 SE (mrad²), and whether it is ahead (lower), tied or behind after the correction; " +
             ("" if len(seeds) == 1 else "over %d training seeds (seeds and frames resampled); " % len(seeds)) +
             family.describe() + ".", "",
             "| SNR (dB) | " + " | ".join("against %s" % m for m in CLASSICAL) + " |",
             "|---|" + "---|" * len(CLASSICAL)]
    for s in snrs:
        cells = []
        for m in CLASSICAL:
            r, adj, v = res[(s, m)]
            cells.append("%+.4g ± %.2g (%s)" % (1e6 * r["diff"], 2e6 * r["se"], v))
        lines.append("| %g | %s |" % (s, " | ".join(cells)))
    return lines


def base(method):
    """A method's name without its training seed ("SemS position (learned) [seed 2]" -> its base)."""
    return method.split(" [seed ")[0]


def pooled(rows):
    """One-target rows with each learned method's seeds pooled: RMSE = sqrt(mean of the seeds' MSE)
    (the seeds score the same frames), the seeds' count in `seeds`."""
    out, groups = [], {}
    for r in rows:
        groups.setdefault((base(r["method"]), r["snr_db"]), []).append(r)
    for (m, snr), rs in groups.items():
        r = dict(rs[0], method=m, seeds=len(rs))
        if len(rs) > 1:
            rmse = math.sqrt(sum(float(x["rmse_rad"]) ** 2 for x in rs) / len(rs))
            r["rmse_rad"], r["rmse_over_crb"] = str(rmse), str(rmse / float(r["crb_rad"]))
        out.append(r)
    return out


def read(path):
    if not os.path.exists(path):
        sys.exit("plot_angle.py: %s is missing: `bash scripts/evaluation/eval_arrays.sh` writes it" % path)
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--table")
    a = ap.parse_args()
    rows = read(os.path.join(a.results, "exp9_angle.csv"))
    one = pooled([r for r in rows if r["part"] == "one_target"])
    two = [r for r in rows if r["part"] == "two_targets"]
    if not one or not two:
        sys.exit("plot_angle.py: exp9_angle.csv has no %s rows" % ("one_target" if not one else "two_targets"))
    k, np_, frames = one[0]["elements"], one[0]["n_pilots"], int(one[0]["frames"])

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    methods = list(dict.fromkeys(r["method"] for r in one))
    seeds = {r["method"]: r["seeds"] for r in one}
    label = {m: m if seeds[m] == 1 else "%s, %d seeds" % (m, seeds[m]) for m in methods}
    for m in methods:
        rs = [r for r in one if r["method"] == m]
        ax.semilogy([float(r["snr_db"]) for r in rs], [float(r["rmse_rad"]) for r in rs], marker="o", label=label[m])
    ax.semilogy([float(r["snr_db"]) for r in one if r["method"] == methods[0]],
                [float(r["crb_rad"]) for r in one if r["method"] == methods[0]], "k--", label="CRB")
    ax.set_xlabel("SNR per resource element (dB)")
    ax.set_ylabel("azimuth RMSE (rad)")
    ax.set_title("one target, %s-element ULA, %s pilots per element" % (k, np_), fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    for m in dict.fromkeys(r["method"] for r in two):
        rs = [r for r in two if r["method"] == m]
        x = [float(r["snr_db"]) for r in rs]
        p = [float(r["both_found"]) for r in rs]
        se = [math.sqrt(v * (1 - v) / int(r["frames"])) for v, r in zip(p, rs)]
        line, = ax2.plot(x, p, marker="o", label=m)
        ax2.fill_between(x, [v - 2 * s for v, s in zip(p, se)], [v + 2 * s for v, s in zip(p, se)],
                         color=line.get_color(), alpha=0.15)
    ax2.axhline(0.95, color="grey", lw=0.8, ls=":", label="95 %")
    ax2.set_xlabel("SNR per resource element (dB)")
    ax2.set_ylabel("share of frames, both found (± 2 SE)")
    ax2.set_ylim(0, 1.02)
    ax2.set_title("two coherent targets 1.5 beamwidths apart: both within ¼ beamwidth", fontsize=10)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle("Experiment 9: azimuth from an array's pilots (%d test frames per point)" % frames, fontsize=11)
    fig.tight_layout()
    png = os.path.join(a.results, "exp9_angle.png")
    fig.savefig(png, dpi=110)

    snrs = list(dict.fromkeys(r["snr_db"] for r in one))
    lines = ["| SNR (dB) | CRB (mrad) | " + " | ".join("%s RMSE (mrad, × CRB)" % label[m] for m in methods) + " |",
             "|---|---|" + "---|" * len(methods)]
    for s in snrs:
        rs = {r["method"]: r for r in one if r["snr_db"] == s}
        crb = float(rs[methods[0]]["crb_rad"])
        cells = ["%.2f (%.2f)" % (1e3 * float(rs[m]["rmse_rad"]), float(rs[m]["rmse_over_crb"])) for m in methods]
        lines.append("| %s | %.2f | %s |" % (s, 1e3 * crb, " | ".join(cells)))
    two_methods = list(dict.fromkeys(r["method"] for r in two))
    lines += ["", "| SNR (dB) | " + " | ".join("%s: both found (± SE)" % m for m in two_methods) + " |",
              "|---|" + "---|" * len(two_methods)]
    for s in snrs:
        rs = {r["method"]: r for r in two if r["snr_db"] == s}
        cells = []
        for m in two_methods:
            p, n = float(rs[m]["both_found"]), int(rs[m]["frames"])
            cells.append("%.3f (± %.3f)" % (p, math.sqrt(p * (1 - p) / n)))
        lines.append("| %s | %s |" % (s, " | ".join(cells)))
    lines += paired_table(a.results)
    table = a.table or os.path.join(a.results, "exp9_angle.md")
    with open(table, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("plot_angle.py: wrote %s and %s" % (png, table))


if __name__ == "__main__":
    main()
