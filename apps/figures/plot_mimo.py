#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Experiment 9's MIMO part: which pilots each transmit element sends, for a target's azimuth
(exp9_mimo*.csv from `sems_eval --experiments 9 --exp9-parts mimo`, as
scripts/evaluation/eval_arrays.sh runs it).

    plot_mimo.py RESULTS

Reads from RESULTS:
  exp9_mimo_masks.csv        every hand form on every standard pattern (the kept one marked),
                             each learned mask (one per training seed) and the virtual array floor:
                             the mean Cramér–Rao bound at 0 dB
  exp9_mimo.csv              each mask's RMSE and root mean CRB per SNR (required)
  exp9_mimo_predictions.csv  every estimate of every frame, packed on first use into
    or .npz                  exp9_mimo_predictions.npz, which everything is then read from (the
                             CSV may go afterwards)
  masks_mimo/*.json          the kept masks (optional: only a run's own folder has them)
  exp9_mimo_budget.csv       the same bounds at fewer pilots (optional: --exp9-parts mimo_budget)
Writes to RESULTS:
  exp9_mimo.md               the bound table (and the pilot budget's), the RMSE table and the paired tests: the learned
                             masks' squared errors against each hand form's on the same frames and
                             noise, at every SNR (paired_stats.two_level: training seeds and
                             frames resampled; a hand form pairs with every seed), one family with
                             Holm's correction over all of them
  exp9_mimo.png              RMSE against SNR beside each mask's CRB and the virtual array floor;
                             with masks_mimo/, the kept masks on the frame's grid beside it
"""
import argparse
import csv
import glob
import json
import math
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402
from matplotlib.gridspec import GridSpec  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired_stats as ps  # noqa: E402

PROG = "plot_mimo.py"
FORMS = ("same pilots", "time division", "frequency division")
LEARNED = "learned"
POLISHED = "random, polished"  # the learner's polish alone from a random mask (bound only)
FLOOR = "virtual array floor"
MASK_FILES = {"same pilots": "same_pilots", "time division": "time_division",
              "frequency division": "frequency_division"}
BOOTSTRAP_SEED = 9  # the experiment's number, as plot_angle.py seeds its tests
BOOTS = 2000


def read(path):
    if not os.path.exists(path):
        sys.exit("%s: %s is missing: `bash scripts/evaluation/eval_arrays.sh` writes it" % (PROG, path))
    with open(path) as f:
        return list(csv.DictReader(f))


def seed_of(text):
    """A CSV's train_seed: None for a hand form (empty), else the seed as an int."""
    return int(text) if text not in ("", None) else None


# ---------------------------------------------------------------------------------------------
# Predictions: packed once, then read from the npz alone.

def pack(csv_path, npz_path):
    """exp9_mimo_predictions.csv -> npz: per series (method, train seed) its estimates and each
    frame's bound (snrs x frames); the truth once, as every mask sees the same frames."""
    rows = read(csv_path)
    snrs = sorted({float(r["snr_db"]) for r in rows})
    frames = 1 + max(int(r["frame"]) for r in rows)
    series = list(dict.fromkeys((r["method"], r["train_seed"]) for r in rows))
    est = {s: np.full((len(snrs), frames), np.nan) for s in series}
    crb = {s: np.full((len(snrs), frames), np.nan) for s in series}
    truth = np.full((len(snrs), frames), np.nan)
    at = {s: i for i, s in enumerate(snrs)}
    for r in rows:
        i, f, key = at[float(r["snr_db"])], int(r["frame"]), (r["method"], r["train_seed"])
        t = float(r["truth_rad"])
        # The paired tests rest on every mask seeing the same frame: a different truth would break them.
        if not math.isnan(truth[i, f]) and truth[i, f] != t:
            sys.exit("%s: %s: frame %d at %g dB has two truths (%r and %r): the masks did not see the same frames"
                     % (PROG, csv_path, f, snrs[i], truth[i, f], t))
        truth[i, f] = t
        est[key][i, f], crb[key][i, f] = float(r["azimuth_rad"]), float(r["crb_rad"])
    np.savez_compressed(npz_path, snr_db=np.array(snrs), truth_rad=truth,
                        methods=np.array([m for m, _ in series]), train_seeds=np.array([s for _, s in series]),
                        **{"est_%d" % k: est[s] for k, s in enumerate(series)},
                        **{"crb_%d" % k: crb[s] for k, s in enumerate(series)})


def predictions(results):
    """{(method, train seed or None): (estimates, per-frame CRB in rad)}, truth, snrs — each array
    snrs x frames — from the npz (packed from the CSV when the CSV is newer or the npz missing);
    None without either."""
    csv_path = os.path.join(results, "exp9_mimo_predictions.csv")
    npz_path = os.path.join(results, "exp9_mimo_predictions.npz")
    if os.path.exists(csv_path) and (not os.path.exists(npz_path) or
                                     os.path.getmtime(csv_path) > os.path.getmtime(npz_path)):
        pack(csv_path, npz_path)
    if not os.path.exists(npz_path):
        return None
    z = np.load(npz_path)
    keys = [(str(m), seed_of(str(s))) for m, s in zip(z["methods"], z["train_seeds"])]
    series = {key: (z["est_%d" % k], z["crb_%d" % k]) for k, key in enumerate(keys)}
    return series, z["truth_rad"], [float(s) for s in z["snr_db"]]


# ---------------------------------------------------------------------------------------------
# Paired tests.

def paired_family(got):
    """The learned masks against each hand form at every SNR, on squared azimuth errors."""
    series, truth, snrs = got
    family = ps.Family("experiment 9 (MIMO): the learned masks against each hand form, every SNR",
                       lower_is_better=True)
    learned = sorted(s for m, s in series if m == LEARNED)
    if not learned:
        return family, learned
    for i, snr in enumerate(snrs):
        # Seed x frame squared errors; a hand form has no seed and pairs with every one (paired_stats.align).
        a = {s: (series[(LEARNED, s)][0][i] - truth[i]) ** 2 for s in learned}
        for form in FORMS:
            if (form, None) not in series:
                continue
            b = {None: (series[(form, None)][0][i] - truth[i]) ** 2}
            key = (snr, form)
            family.add(key, ps.compare(a, b, ps.rng_for(BOOTSTRAP_SEED, key), BOOTS))
    return family, learned


def paired_lines(got):
    if got is None:
        return ["", "No per-frame estimates (exp9_mimo_predictions.csv or .npz): no paired tests."]
    family, learned = paired_family(got)
    if not len(family):
        return ["", "The per-frame estimates hold no learned mask or no hand form: no paired tests."]
    lines = ["", "**Paired tests**, on the same frames and noise: the learned masks' squared azimuth error minus "
             "each hand form's, mean over %d training seeds and the frames (mrad²), its bootstrap SE (seeds and "
             "frames resampled, %d resamples; the hand form pairs with every seed), the learned RMSE (pooled over "
             "the seeds: root of the mean squared error) over the hand form's, and whether the learned masks "
             "are ahead (lower error), tied or behind after the correction; %s." % (
                 len(learned), BOOTS, family.describe()), "",
             "| SNR (dB) | against | learned − form (mrad²) | SE (mrad²) | RMSE ratio learned / form | p (Holm) | reading |",
             "|---|---|---:|---:|---:|---:|---|"]
    for (snr, form), r, p, v in family.results():
        ratio = math.sqrt(r["a"] / r["b"]) if r["b"] > 0 else float("nan")
        lines.append("| %g | %s | %+.4g | %.2g | %.3f | %.2g | %s |" % (
            snr, form, 1e6 * r["diff"], 1e6 * r["se"], ratio, p, v))
    return lines


# ---------------------------------------------------------------------------------------------
# Tables from the CSVs.

def per_element(text):
    """pilots_per_element as written ("16/16"); "0/0/..." is a mask whose every pilot all
    elements send (mimo_mask::pilots_per_element counts only pilots one element sends alone)."""
    counts = [int(c) for c in text.split("/")] if text else []
    if counts and not any(counts):
        return "all %d send every pilot" % len(counts)
    return text


def bound_lines(masks):
    """Each form's kept pattern and its bound against the floor; every learned seed and their mean."""
    floor = [float(r["mean_crb_0db_rad2"]) for r in masks if r["form"] == FLOOR]
    if not floor:
        return ["", "exp9_mimo_masks.csv has no \"%s\" row: no bound table." % FLOOR], None
    floor = floor[0]
    root_floor = math.sqrt(floor)

    def row(name, pattern, per, crb, others=""):
        return "| %s | %s | %s | %.3f | %.3f | %s |" % (
            name, pattern, per, 1e3 * math.sqrt(crb), math.sqrt(crb) / root_floor, others)

    n_p = masks[0]["n_pilots"]
    lines = ["", "**The bound** (exp9_mimo_masks.csv): %s pilots in all, the azimuth's Cramér–Rao bound with delay, "
             "Doppler and complex gain unknown, its mean over the scene's azimuths at 0 dB per pilot; the root of "
             "that mean (mrad) and its ratio to the root of the virtual array floor (%.3f mrad: the bound no mask "
             "whose pilots each come from one element can beat). Each hand form on the standard pattern with the "
             "lowest bound; its other patterns beside it." % (n_p, 1e3 * root_floor), "",
             "| mask | pattern | pilots per element | root mean CRB at 0 dB (mrad) | × floor | other patterns, or the learned mask before its polish (× floor) |",
             "|---|---|---|---:|---:|---|"]
    for form in FORMS:
        tried = [r for r in masks if r["form"] == form]
        kept = [r for r in tried if r["chosen"] == "1"]
        if not kept:
            continue
        others = ", ".join("%s %.3f" % (r["pattern"], math.sqrt(float(r["mean_crb_0db_rad2"])) / root_floor)
                           for r in tried if r is not kept[0])
        lines.append(row(form, kept[0]["pattern"], per_element(kept[0]["pilots_per_element"]),
                         float(kept[0]["mean_crb_0db_rad2"]), others))
    learned = [r for r in masks if r["form"] == LEARNED]
    for r in learned:
        before = r.get("before_polish_rad2", "")
        lines.append(row("learned, seed %s" % r["train_seed"], "learned", per_element(r["pilots_per_element"]),
                         float(r["mean_crb_0db_rad2"]),
                         "before the polish %.3f" % (math.sqrt(float(before)) / root_floor) if before else ""))
    if len(learned) > 1:  # the mean of the seeds' mean CRB (rad²), then its root
        lines.append(row("learned, mean of %d seeds" % len(learned), "", "",
                         float(np.mean([float(r["mean_crb_0db_rad2"]) for r in learned]))))
    for r in [r for r in masks if r["form"] == POLISHED]:
        before = r.get("before_polish_rad2", "")
        lines.append(row("random, polished, seed %s" % r["train_seed"], "random", per_element(r["pilots_per_element"]),
                         float(r["mean_crb_0db_rad2"]),
                         "before the polish %.3f" % (math.sqrt(float(before)) / root_floor) if before else ""))
    return lines, floor


def budget_lines(rows):
    """Per pilot count: each hand form's best bound, the learned masks' (mean over seeds of the mean
    CRB, its root; the seeds' range; before the polish), the floor, all × the floor."""
    if not rows:
        return []
    lines = ["", "**The pilot budget** (exp9_mimo_budget.csv): the same bounds with fewer pilots, each as its root "
             "mean CRB at 0 dB over the floor's (× floor; the floor itself in mrad); learned: the mean over its "
             "training seeds, the seeds' range, and the same before the polish; random, polished: the learner's "
             "polish alone from a random mask of each seed (mean over seeds).", "",
             "| N_p | floor (mrad) | " + " | ".join(FORMS) + " | learned | learned, seeds | learned before the polish "
             "| random, polished |",
             "|---:|---:|" + "---:|" * (len(FORMS) + 2) + "---|---:|"]
    for n_p in sorted({int(r["n_pilots"]) for r in rows}):
        at = [r for r in rows if int(r["n_pilots"]) == n_p]
        floor = [float(r["mean_crb_0db_rad2"]) for r in at if r["form"] == FLOOR]
        if not floor:
            continue
        root_floor = math.sqrt(floor[0])
        cells = []
        for form in FORMS:
            kept = [float(r["mean_crb_0db_rad2"]) for r in at if r["form"] == form and r["chosen"] == "1"]
            cells.append("%.3f" % (math.sqrt(kept[0]) / root_floor) if kept else "")
        learned = [float(r["mean_crb_0db_rad2"]) for r in at if r["form"] == LEARNED]
        before = [float(r["before_polish_rad2"]) for r in at if r["form"] == LEARNED and r.get("before_polish_rad2")]
        ratios = [math.sqrt(v) / root_floor for v in learned]
        cells.append("%.3f" % (math.sqrt(np.mean(learned)) / root_floor) if learned else "")
        cells.append("%.3f–%.3f" % (min(ratios), max(ratios)) if ratios else "")
        cells.append("%.3f" % (math.sqrt(np.mean(before)) / root_floor) if before else "")
        polished = [float(r["mean_crb_0db_rad2"]) for r in at if r["form"] == POLISHED]
        cells.append("%.3f" % (math.sqrt(np.mean(polished)) / root_floor) if polished else "")
        lines.append("| %d | %.3f | %s |" % (n_p, 1e3 * root_floor, " | ".join(cells)))
    return lines


def method_rows(rows):
    """{method: {snr: [rows, one per training seed]}} in the CSV's order."""
    out = {}
    for r in rows:
        out.setdefault(r["method"], {}).setdefault(float(r["snr_db"]), []).append(r)
    return out


def rmse_lines(rows, floor):
    by = method_rows(rows)
    methods = list(by)
    snrs = sorted({float(r["snr_db"]) for r in rows})
    n_learned = max((len(v) for v in by.get(LEARNED, {}).values()), default=0)
    lines = ["", "**RMSE** (exp9_mimo.csv, %s frames per point): the maximum-likelihood estimate's RMSE (mrad) and, "
             "in brackets, its ratio to the mask's own root mean CRB over the same frames%s; the virtual array "
             "floor at each SNR for reference." % (
                 rows[0]["frames"], "" if not n_learned else
                 "; learned: the mean over %d training seeds of the RMSE and of the ratio, the seeds' range after it"
                 % n_learned), "",
             "| SNR (dB) | floor (mrad) | " + " | ".join(methods) + " |",
             "|---|---:|" + "---:|" * len(methods)]
    for s in snrs:
        cells = []
        for m in methods:
            rs = by[m].get(s, [])
            if not rs:
                cells.append("")
                continue
            rmse = [1e3 * float(r["rmse_rad"]) for r in rs]
            ratio = np.mean([float(r["rmse_over_crb"]) for r in rs])
            cell = "%.3g (%.2f)" % (np.mean(rmse), ratio)
            if len(rs) > 1:
                cell += " [%.3g–%.3g]" % (min(rmse), max(rmse))
            cells.append(cell)
        fl = "%.3g" % (1e3 * math.sqrt(floor / 10 ** (s / 10))) if floor else ""
        lines.append("| %g | %s | %s |" % (s, fl, " | ".join(cells)))
    return lines


# ---------------------------------------------------------------------------------------------
# Figure.

def plot_rmse(ax, rows, floor, colours):
    by = method_rows(rows)
    snrs = sorted({float(r["snr_db"]) for r in rows})
    for k, (m, per_snr) in enumerate(by.items()):
        c = colours[k % len(colours)]
        x = [s for s in snrs if s in per_snr]
        seeds = max(len(per_snr[s]) for s in x)
        if seeds > 1:  # each seed faint, their mean bold
            for j in range(seeds):
                ax.semilogy(x, [float(per_snr[s][j]["rmse_rad"]) for s in x], color=c, alpha=0.3, lw=0.8)
        ax.semilogy(x, [np.mean([float(r["rmse_rad"]) for r in per_snr[s]]) for s in x], marker="o", color=c,
                    label=m if seeds == 1 else "%s (mean of %d seeds)" % (m, seeds))
        # The mask's bound over the same frames: root of the mean per-frame CRB (over the seeds too).
        ax.semilogy(x, [math.sqrt(np.mean([float(r["crb_rad"]) ** 2 for r in per_snr[s]])) for s in x],
                    ls="--", color=c, lw=1)
    if floor:
        xs = np.linspace(min(snrs), max(snrs), 50)
        ax.semilogy(xs, np.sqrt(floor / 10 ** (xs / 10)), "k:", lw=1.4, zorder=5, label=FLOOR)
    ax.plot([], [], "--", color="grey", lw=1, label="each mask's root mean CRB")
    ax.set_xlabel("SNR per pilot (dB)")
    ax.set_ylabel("azimuth RMSE (rad)")
    ax.set_title("maximum-likelihood azimuth, %s frames per point" % rows[0]["frames"], fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower left")  # below the floor at low SNR: no curve there


def load_masks(results, masks):
    """[(title, mask json)] of the kept masks to draw: time division, frequency division and the
    first learned seed, from RESULTS/masks_mimo/ (only a run's own folder has it); [] without."""
    folder = os.path.join(results, "masks_mimo")
    if not glob.glob(os.path.join(folder, "*.json")):
        return []
    wanted = []
    for form in ("time division", "frequency division"):
        kept = [r for r in masks if r["form"] == form and r["chosen"] == "1"]
        wanted.append(("%s (%s pattern)" % (form, kept[0]["pattern"]) if kept else form,
                       MASK_FILES[form] + ".json"))
    seeds = sorted(int(r["train_seed"]) for r in masks if r["form"] == LEARNED)
    if seeds:
        wanted.append(("learned, seed %d" % seeds[0], "learned_s%d.json" % seeds[0]))
    out = []
    for title, name in wanted:
        path = os.path.join(folder, name)
        if os.path.exists(path):
            with open(path) as f:
                out.append((title, json.load(f)))
    return out


def draw_mask(ax, title, m, element_colours):
    """One MIMO mask on the symbols x subcarriers grid, each pilot coloured by its transmit element
    (grey where every element sends it). An image, so the cells fill the grid at any figure size."""
    grid = m["mask"]
    n, n_sc = grid["n_symbols"], grid["n_subcarriers"]
    pilots = np.array(grid["pilots"]).reshape(-1, 2)  # [symbol n, subcarrier m] per pilot
    tx = np.array(m["transmit"])
    image = np.full((n, n_sc, 3), 0.95)
    for (sym, sc), e in zip(pilots, tx):
        image[sym, sc] = to_rgb("0.5" if e < 0 else element_colours[e % len(element_colours)])
    ax.imshow(image, interpolation="nearest", aspect="equal")  # symbol 0 on top, as a frame is read
    counts = [int((tx == e).sum()) for e in range(m["n_transmit"])]
    ax.set_title("%s: %s per element" % (title, "/".join(map(str, counts))), fontsize=9)
    ax.set_ylabel("symbol", fontsize=8)
    ax.tick_params(labelsize=7)


def plot(results, rows, masks, floor):
    drawn = load_masks(results, masks)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    # Transmit elements in colours of their own, unlike the methods' on the left.
    element_colours = ["#7b2cbf", "#00a5b5", "#c8a200", "#555555", "#e377c2", "#8c564b"]
    if drawn:
        fig = plt.figure(figsize=(12.5, 6.4))
        gs = GridSpec(len(drawn), 2, figure=fig, width_ratios=[1.35, 1])
        plot_rmse(fig.add_subplot(gs[:, 0]), rows, floor, colours)
        for i, (title, m) in enumerate(drawn):
            ax = fig.add_subplot(gs[i, 1])
            draw_mask(ax, title, m, element_colours)
            if i == len(drawn) - 1:
                ax.set_xlabel("subcarrier", fontsize=8)
        n_t = max(m["n_transmit"] for _, m in drawn)
        handles = [plt.Line2D([], [], marker="s", ls="", color=element_colours[e % len(element_colours)],
                              label="transmit element %d" % e) for e in range(n_t)]
        fig.legend(handles=handles, loc="lower right", ncol=n_t, fontsize=8, frameon=False)
    else:
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        plot_rmse(ax, rows, floor, colours)
    n_p = rows[0]["n_pilots"]
    fig.suptitle("Experiment 9 (MIMO): which pilots each transmit element sends, %s pilots in all" % n_p,
                 fontsize=11)
    fig.tight_layout(rect=(0, 0.03, 1, 1) if drawn else (0, 0, 1, 1))
    png = os.path.join(results, "exp9_mimo.png")
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


# ---------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", help="the folder with exp9_mimo*.csv; the outputs go there too")
    a = ap.parse_args()
    rows = read(os.path.join(a.results, "exp9_mimo.csv"))
    if not rows:
        sys.exit("%s: %s has no rows" % (PROG, os.path.join(a.results, "exp9_mimo.csv")))
    masks = read(os.path.join(a.results, "exp9_mimo_masks.csv"))
    bounds, floor = bound_lines(masks)

    png = plot(a.results, rows, masks, floor)
    lines = ["Made by apps/figures/plot_mimo.py from exp9_mimo*.csv; run: `bash scripts/evaluation/eval_arrays.sh`.",
             "", "Experiment 9 (MIMO): the pilots each transmit element sends, for a target's azimuth — the hand "
             "forms (same pilots, time division, frequency division) and the learned masks, scored by their "
             "Cramér–Rao bound and by the maximum-likelihood estimator on the same frames and noise."]
    budget = os.path.join(a.results, "exp9_mimo_budget.csv")
    lines += bounds + (budget_lines(read(budget)) if os.path.exists(budget) else []) + rmse_lines(rows, floor) + \
        paired_lines(predictions(a.results))
    md = os.path.join(a.results, "exp9_mimo.md")
    with open(md, "w") as f:
        f.write("\n".join(lines) + "\n")
    npz = os.path.join(a.results, "exp9_mimo_predictions.npz")
    print("%s: wrote %s and %s%s" % (PROG, png, md, " (from %s)" % npz if os.path.exists(npz) else ""))


if __name__ == "__main__":
    main()
