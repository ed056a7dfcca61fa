#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Draw one PNG per sems_eval experiment 1 to 6 from its CSVs (7 to 9: plot_kinematic.py,
plot_range.py, plot_tracks.py, plot_angle.py, plot_array_classes.py).

    /usr/bin/python3 apps/figures/plot_results.py docs/results            # PNGs next to the CSVs
    /usr/bin/python3 apps/figures/plot_results.py /tmp/eval --out /tmp/png --tsne-iter 250

Missing CSVs are skipped (a partial run still plots what it has); rows in
shipped_<csv> files (from `sems_eval --only-shipped`) and bound_<csv> files (bounds from a
separate run, e.g. `docs/results/classifier_bayes.py --csv`) are added to their experiment.
Learned methods trained with several seeds (the train_seed column, `sems_eval --seeds`) are
drawn as the mean over the seeds with min–max bars, and tabulated as mean ± half-range;
rows with train_seed "none" (no training) and CSVs without the column (one seed) are drawn
as single lines. The tables' comparison of the learned mask with the best hand pattern
(experiment 1) is a paired test on the per-frame predictions sems_eval keeps beside the CSVs
(apps/figures/claims.py, which also writes claims.md; apps/figures/paired_stats.py). The t-SNE of
experiment 2 is an exact t-SNE in numpy (perplexity 30, early exaggeration), so no
scikit-learn is needed.
"""
import argparse
import csv
import math
import os
import sys
from collections import OrderedDict, defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.text  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import claims  # noqa: E402  (the paired tests on the kept predictions)

CLASS_COLOURS = {"pedestrian": "tab:blue", "car": "tab:orange", "drone": "tab:green"}


def read_csv(path):
    """Rows of a sems_eval CSV, plus those of shipped_<name> (the rows of `sems_eval
    --only-shipped` for the same experiment) and bound_<name> (a bound computed by a separate
    documented run, e.g. docs/results/classifier_bayes.py) beside it, when present."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for prefix in ("shipped_", "bound_"):
        extra = os.path.join(os.path.dirname(path), prefix + os.path.basename(path))
        if os.path.exists(extra):
            with open(extra, newline="") as f:
                rows += list(csv.DictReader(f))
    return rows


def fnum(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float("nan")


def train_seed(r):
    """A row's training seed, or None: a method without training, or a CSV written before
    the train_seed column (one seed)."""
    s = r.get("train_seed") or "none"
    return None if s == "none" else s


def n_seeds(rows):
    """How many training seeds the rows hold (0: no trained method, or an old CSV)."""
    return len({train_seed(r) for r in rows} - {None})


def over_seeds(values):
    """(mean, min, max, n) of one value per training seed, NaNs left out."""
    v = [x for x in values if not math.isnan(x)]
    if not v:
        return float("nan"), float("nan"), float("nan"), 0
    return sum(v) / len(v), min(v), max(v), len(v)


def series(rows, key_fields, x="snr_db", y="accuracy"):
    """{key: (xs, means, mins, maxs, counts)} sorted by x, key = tuple of key_fields; at each
    x the statistics are over the rows' training seeds (one value per seed)."""
    out = OrderedDict()
    for r in rows:
        k = tuple(r[f] for f in key_fields)
        per_seed = out.setdefault(k, {}).setdefault(fnum(r[x]), OrderedDict())
        per_seed.setdefault(train_seed(r), []).append(fnum(r[y]))
    result = OrderedDict()
    for k, by_x in out.items():
        pts = []
        for xv in sorted(by_x):
            # Rows repeated within one seed (none expected) are averaged before the spread.
            pts.append((xv,) + over_seeds([sum(v) / len(v) for v in by_x[xv].values()]))
        result[k] = tuple(zip(*pts))
    return result


def labels(rows):
    """{(method, mask): legend label}: the method's name, with its mask when the same method
    runs on several masks in these rows (so their lines are not merged)."""
    masks = OrderedDict()
    for r in rows:
        masks.setdefault(r["method"], OrderedDict())[r.get("mask", "")] = None
    out = OrderedDict()
    for method, ms in masks.items():
        for m in ms:
            out[(method, m)] = method if len(ms) == 1 else "%s (%s)" % (method, m)
    return out


def draw(ax, xs, means, los, his, counts, label, logy=False, dodge=0.0, **st):
    """One line; with min–max bars (and shifted by dodge in x) where several training seeds
    were averaged. Returns the legend handle."""
    xs, means = list(xs), list(means)
    if logy:  # a non-positive value has no place on a log axis
        means = [m if m > 0 else float("nan") for m in means]
    if max(counts, default=0) <= 1:
        return ax.plot(xs, means, label=label, **st)[0]
    lo = [max(m - l, 0.0) if c > 1 else 0.0 for m, l, c in zip(means, los, counts)]
    hi = [max(h - m, 0.0) if c > 1 else 0.0 for m, h, c in zip(means, his, counts)]
    if logy:  # a bar reaching zero would run off the axis: stop it at a tenth of the mean
        lo = [min(d, 0.9 * m) if m > 0 else 0.0 for d, m in zip(lo, means)]
    return ax.errorbar([x + dodge for x in xs], means, yerr=[lo, hi], label=label, capsize=2.5, elinewidth=0.9,
                       **st)


def dodges(lines):
    """{key: x shift} for the lines of series() that carry seed bars: spread over a fifth of
    the smallest SNR step (at most 1.5 dB), so bars at the same SNR do not hide each other."""
    barred = [k for k, line in lines.items() if max(line[4], default=0) > 1]
    xs = sorted({x for line in lines.values() for x in line[0]})
    step = min((b - a for a, b in zip(xs, xs[1:])), default=1.0)
    n = len(barred)
    if n < 2:
        return {}
    return {k: (i / (n - 1) - 0.5) * min(0.2 * step, 1.5) for i, k in enumerate(barred)}


def plot_lines(ax, rows, y, logy=False):
    """Each (method, mask) of the rows as one line against SNR, in CSV order; returns the
    legend handles in that order (matplotlib would list bar lines after plain ones)."""
    names = labels(rows)
    lines = series(rows, ["method", "mask"], y=y)
    shift = dodges(lines)
    return [draw(ax, *line, label=names[k], logy=logy, dodge=shift.get(k, 0.0), **style(*k))
            for k, line in lines.items()]


# Line styles of the bounds by their pilots (several bounds share a panel).
CRB_LINESTYLE = {"random": "--", "random subcarriers, one symbol": ":", "SemS pilots": "-."}


# One colour per (method, mask) for the whole run, so a method keeps its colour across panels
# and figures (matplotlib's cycle restarts per axes, in each panel's own line order).
_COLOURS = {}


def colour(method, mask=""):
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"] + ["#393b79", "#8c6d31", "#843c39", "#7b4173",
                                                               "#637939", "#3182bd", "#e6550d", "#31a354"]
    return _COLOURS.setdefault((method, mask), palette[len(_COLOURS) % len(palette)])


def style(method, mask=""):
    st = _style(method, mask)
    st.setdefault("color", colour(method, mask))
    return st


def _style(method, mask=""):
    if method.startswith("Perfect CSI"):
        return dict(linestyle="--", marker="s")
    if method.startswith("SVM"):
        return dict(linestyle=":", marker="^")
    if method.startswith("MSE"):
        return dict(linestyle="-.", marker="v")
    if method.startswith("Bayes classifier from"):
        # A Monte-Carlo classifier of a given prior size (classifier_bayes.py --as-decoder): a
        # decoder that knows as many draws as a network's training set (one colour per size).
        return dict(linestyle="-.", marker="P", markersize=5)
    if method.startswith("Bayes"):
        # The classification bound: black like the CRB; dotted with small dots where its
        # Monte-Carlo estimate has not converged (a reachable accuracy below the bound).
        if "not converged" in method:
            return dict(linestyle=":", color="black", marker=".", markersize=4)
        return dict(linestyle="--", color="black", marker=None)
    if method.startswith("CRB"):
        # Black: the bound of the scene; grey: the single-path bound drawn in multipath.
        colour = "dimgrey" if method.startswith("CRB (single path") else "black"
        return dict(linestyle=CRB_LINESTYLE.get(mask, "--"), color=colour, marker=None)
    if method.startswith("Shipped"):
        return dict(linestyle="-", marker="D", markersize=4, alpha=0.8)
    if method.startswith("SemS"):
        return dict(linestyle="-", marker="o", linewidth=2)
    return dict(linestyle="-", marker="x")


def footer(fig, rows):
    if rows:
        frames = "/".join(sorted({r.get("n_frames", "?") for r in rows}))
        seeds = "/".join(sorted({r.get("seed", "?") for r in rows}))
        text = "test frames per point: %s, seed %s" % (frames, seeds)
        n = n_seeds(rows)
        if n > 1:
            text += "; mean of %d training seeds, bars = min–max (shifted apart in SNR)" % n
        fig.text(0.01, 0.005, text, fontsize=7, color="grey")


def plot_accuracy(rows, scenario, axes, title):
    rs = [r for r in rows if r["scenario"] == scenario]
    for metric, ax in zip(("accuracy", "macro_f1"), axes):
        handles = plot_lines(ax, rs, metric)
        ax.set_xlabel("SNR (dB)")
        ax.set_ylabel("accuracy" if metric == "accuracy" else "macro-F1")
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
        ax.set_title("%s: %s" % (title, "accuracy" if metric == "accuracy" else "macro-F1"), fontsize=10)
    axes[0].legend(handles=handles, fontsize=7, loc="lower right")


def exp1(d, out):
    rows = read_csv(os.path.join(d, "exp1_recognition.csv"))
    if not rows:
        return None
    # One row per scene: the paper's (approaching targets), then the "any" heading scene.
    scenes = [s for s in ("default", "any") if any(r["scenario"] == s for r in rows)]
    fig, axes = plt.subplots(len(scenes), 2, figsize=(11, 4.2 * len(scenes)), squeeze=False)
    for ax_row, s in zip(axes, scenes):
        plot_accuracy(rows, s, ax_row, "Recognition" if s == "default" else "Any heading")
    footer(fig, rows)
    fig.tight_layout()
    path = os.path.join(out, "exp1_recognition.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def exp3(d, out):
    rows = read_csv(os.path.join(d, "exp3_conditions.csv"))
    if not rows:
        return None
    scen = [s for s in ("no_md", "clutter") if any(r["scenario"] == s for r in rows)]
    fig, axes = plt.subplots(1, len(scen), figsize=(5.5 * len(scen), 4.2), squeeze=False)
    for ax, s in zip(axes[0], scen):
        handles = plot_lines(ax, [r for r in rows if r["scenario"] == s], "accuracy")
        ax.legend(handles=handles, fontsize=7, loc="lower right") # each panel: clutter adds the MTI rows
        ax.set_title({"no_md": "without micro-Doppler", "clutter": "strong clutter"}[s], fontsize=10)
        ax.set_xlabel("SNR (dB)")
        ax.set_ylabel("accuracy")
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
    footer(fig, rows)
    fig.tight_layout()
    path = os.path.join(out, "exp3_conditions.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def exp4(d, out):
    rows = read_csv(os.path.join(d, "exp4_delay.csv"))
    if not rows:
        return None
    # The multipath bound's mean over the test frames is infinite when a frame's paths are not
    # identifiable (its CRB is): draw its median sqrt(CRB) instead, and say so in the label.
    rows = [dict(r, mae_index=r["median_abs_error_index"], method=r["method"][:-1] + ", median √CRB)")
            if r["method"].startswith("CRB (multipath") and math.isinf(fnum(r["mae_index"])) else r
            for r in rows]
    scen = [s for s in ("single", "multipath") if any(r["scenario"] == s for r in rows)]
    # Each panel has its own methods and bounds (about 17 lines, long names): one panel per
    # row, its legend beside it.
    fig, axes = plt.subplots(len(scen), 1, figsize=(11, 4.4 * len(scen)), squeeze=False)
    for ax, s in zip(axes[:, 0], scen):
        ax.set_yscale("log")
        handles = plot_lines(ax, [r for r in rows if r["scenario"] == s], "mae_index", logy=True)
        ax.set_title("delay MAE, %s" % ("single path" if s == "single" else "multipath"), fontsize=10)
        ax.set_xlabel("SNR (dB)")
        ax.set_ylabel("MAE (delay index, 1 = 5 m)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(handles=handles, fontsize=6.5, loc="center left", bbox_to_anchor=(1.01, 0.5))
    footer(fig, rows)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    path = os.path.join(out, "exp4_delay.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def exp5(d, out):
    rows = read_csv(os.path.join(d, "exp5_pilot_budget.csv"))
    if not rows:
        return None
    fig, ax = plt.subplots(figsize=(6, 4.2))
    by_np = OrderedDict(sorted(series(rows, ["n_pilots"], y="mae_index").items(), key=lambda kv: int(kv[0][0])))
    shift = dodges(by_np)
    ax.set_yscale("log")
    for k, line in by_np.items():
        draw(ax, *line, label="N_p = %s" % k[0], logy=True, dodge=shift.get(k, 0.0), marker="o")
    ax.set_title("SemS delay MAE vs pilot budget (multipath)", fontsize=10)
    ax.set_xlabel("SNR (dB)")
    ax.set_ylabel("MAE (delay index)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    footer(fig, rows)
    fig.tight_layout()
    path = os.path.join(out, "exp5_pilot_budget.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def label_points(ax, placed):
    """Names each point beside it: to its left in the right third of the axes (so the text stays
    inside), and moved a line down (then up) while it would overprint a label or a point
    already drawn; a moved label gets a thin leader line to its point, so that it cannot be
    read as naming a neighbour."""
    ax.autoscale_view()
    renderer = ax.figure.canvas.get_renderer()
    boxes = []
    for x, y, name in placed:
        right = ax.transAxes.inverted().transform(ax.transData.transform((x, y)))[0] > 0.67
        for dy in (2, -8, 12, -18, 22, -28, 32):
            leader = dict(arrowstyle="-", lw=0.5, color="0.5", shrinkA=0, shrinkB=3) if dy != 2 else None
            text = ax.annotate(name, (x, y), fontsize=7, xytext=(-4 if right else 4, dy),
                               textcoords="offset points", ha="right" if right else "left", arrowprops=leader)
            text.update_positions(renderer)
            box = matplotlib.text.Text.get_window_extent(text, renderer)  # the text's box, not its leader's
            if not any(box.overlaps(b) for b in boxes):
                break
            text.remove()
            text = None
        if text is None:  # nowhere free: the first place, overprinting
            text = ax.annotate(name, (x, y), fontsize=7, xytext=(-4 if right else 4, 2),
                               textcoords="offset points", ha="right" if right else "left")
            box = text.get_window_extent(renderer)
        boxes.append(box)


def exp6(d, out):
    rows = read_csv(os.path.join(d, "exp6_cost.csv"))
    if not rows:
        return None
    acc = [r for r in rows if r["metric"] == "accuracy" and r["experiment"] == "1" and r["scenario"] == "default"]
    mae = [r for r in rows if r["metric"] == "mae_index" and r["experiment"] == "4" and r["scenario"] == "multipath"]

    def at(rs, snr):
        avail = sorted({fnum(r["snr_db"]) for r in rs})
        if not avail:
            return [], None
        s = min(avail, key=lambda v: abs(v - snr))
        return [r for r in rs if fnum(r["snr_db"]) == s], s

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, (rs, snr), ylab, logy in ((axes[0], at(acc, 10.0), "accuracy", False),
                                      (axes[1], at(mae, 30.0), "MAE (delay index)", True)):
        # One point per method (and pilot count): the mean over its training seeds, the
        # value's min–max over them as a bar.
        points = OrderedDict()
        for r in rs:
            points.setdefault((r["method"], r.get("mask", ""), r["n_pilots"]), []).append(r)
        names = labels(rs)
        if logy:
            ax.set_yscale("log")
        ax.set_xscale("log")
        placed = []
        for (method, mask, _), prs in points.items():
            x = over_seeds([fnum(r["us_per_frame"]) for r in prs])[0]
            y, lo, hi, n = over_seeds([fnum(r["value"]) for r in prs])
            if not (x > 0) or math.isnan(y):
                continue
            marker = style(method).get("marker") or "o"
            if n > 1:
                ax.errorbar([x], [y], yerr=[[y - lo], [hi - y]], fmt=marker, markersize=6, capsize=2.5)
            else:
                ax.scatter([x], [y], s=40, marker=marker)
            placed.append((x, y, names[(method, mask)]))
        label_points(ax, placed)
        ax.set_xlabel("inference time per frame (us, this machine)")
        ax.set_ylabel(ylab)
        ax.grid(alpha=0.3, which="both")
        ax.set_title("%s at %s dB" % ("recognition" if not logy else "delay, multipath", snr), fontsize=10)
    footer(fig, rows)
    fig.tight_layout()
    path = os.path.join(out, "exp6_cost.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def tsne(x, perplexity=30.0, iters=500, seed=0):
    """Exact t-SNE (van der Maaten & Hinton 2008): binary-searched Gaussian affinities,
    symmetrised; Student-t similarities; gradient descent with momentum and gains;
    early exaggeration 12 for the first 100 iterations."""
    x = np.asarray(x, dtype=np.float64)
    n = x.shape[0]
    x = (x - x.mean(0)) / (x.std(0) + 1e-12)
    d2 = np.sum(x * x, 1)[:, None] + np.sum(x * x, 1)[None, :] - 2 * x @ x.T
    np.fill_diagonal(d2, 0.0)
    d2 = np.maximum(d2, 0.0)
    perplexity = min(perplexity, (n - 1) / 3.0)
    target = math.log(perplexity)
    p = np.zeros((n, n))
    for i in range(n):
        lo, hi, beta = 0.0, np.inf, 1.0
        di = np.delete(d2[i], i)
        for _ in range(60):
            w = np.exp(-(di - di.min()) * beta)
            s = w.sum()
            h = math.log(s) + beta * np.sum((di - di.min()) * w) / s
            if abs(h - target) < 1e-5:
                break
            if h > target:
                lo = beta
                beta = beta * 2 if hi == np.inf else (beta + hi) / 2
            else:
                hi = beta
                beta = (beta + lo) / 2
        p[i, np.arange(n) != i] = w / s
    p = (p + p.T) / (2 * n)
    p = np.maximum(p, 1e-12)
    rng = np.random.default_rng(seed)
    y = rng.normal(0, 1e-4, (n, 2))
    vel = np.zeros_like(y)
    gains = np.ones_like(y)
    for it in range(iters):
        exag = 12.0 if it < 100 else 1.0
        sy = np.sum(y * y, 1)
        num = 1.0 / (1.0 + sy[:, None] + sy[None, :] - 2 * y @ y.T)
        np.fill_diagonal(num, 0.0)
        q = np.maximum(num / num.sum(), 1e-12)
        pq = (exag * p - q) * num
        grad = 4 * ((np.diag(pq.sum(1)) - pq) @ y)
        mom = 0.5 if it < 250 else 0.8
        gains = np.where(np.sign(grad) != np.sign(vel), gains + 0.2, gains * 0.8)
        gains = np.maximum(gains, 0.01)
        vel = mom * vel - 200.0 * gains * grad
        y = y + vel
        y = y - y.mean(0)
    return y


def exp2(d, out, iters):
    rows = read_csv(os.path.join(d, "exp2_tsne_features.csv"))
    if not rows:
        return None
    feats = sorted((k for k in rows[0] if k.startswith("f") and k[1:].isdigit()), key=lambda k: int(k[1:]))
    by_method = OrderedDict()
    for r in rows:
        by_method.setdefault(r["method"], []).append(r)
    n = len(by_method)
    cols = 2 if n > 1 else 1
    nrows = (n + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.6 * nrows), squeeze=False)
    for ax, (method, rs) in zip(axes.flat, by_method.items()):
        x = np.array([[fnum(r[f]) for f in feats] for r in rs])
        y = tsne(x, iters=iters)
        labels = [r["class_name"] for r in rs]
        for cls, colour in CLASS_COLOURS.items():
            sel = [i for i, l in enumerate(labels) if l == cls]
            if sel:
                ax.scatter(y[sel, 0], y[sel, 1], s=6, c=colour, label=cls)
        acc = np.mean([r["predicted"] == r["class_id"] for r in rs])
        ax.set_title("%s (accuracy %.2f at %s dB)" % (method, acc, rs[0]["snr_db"]), fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    axes[0][0].legend(fontsize=8, markerscale=2)
    fig.tight_layout()
    path = os.path.join(out, "exp2_tsne.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def cell(values, fmt):
    """One value per training seed: the value, or mean ± half-range over several seeds."""
    m, lo, hi, n = over_seeds(values)
    if n == 0:
        return "–"
    if n == 1:
        return fmt % m
    return (fmt + " ± " + fmt) % (m, (hi - lo) / 2)


def pivot(rows, row_key, value, fmt="%.3f"):
    """Markdown table: one line per row_key value (a method is named with its mask when it
    runs on several), one column per SNR; several training seeds give mean ± half-range."""
    snrs = sorted({fnum(r["snr_db"]) for r in rows})
    names = labels(rows) if row_key == "method" else None
    table = OrderedDict()
    for r in rows:
        k = names[(r["method"], r.get("mask", ""))] if names else r[row_key]
        table.setdefault(k, {}).setdefault(fnum(r["snr_db"]), []).append(fnum(r[value]))
    head = "| %s | %s |" % (row_key, " | ".join("%g dB" % s for s in snrs))
    lines = [head, "|" + "---|" * (len(snrs) + 1)]
    for k, vals in table.items():
        lines.append("| %s | %s |" % (k, " | ".join(cell(vals.get(s, []), fmt) for s in snrs)))
    return "\n".join(lines)


def tables(d, boots=claims.BOOTSTRAP, seed=claims.SEED):
    """All result tables as markdown (what docs/RESULTS.md quotes). The learned mask against the
    best hand pattern is a paired test on the kept predictions (apps/figures/claims.py); without
    them its section names the missing file and the command that writes it."""
    out = []
    n = max((n_seeds(read_csv(os.path.join(d, f)) or []) for f in (
        "exp1_recognition.csv", "exp3_conditions.csv", "exp4_delay.csv", "exp5_pilot_budget.csv")), default=0)
    if n > 1:
        out += ["Learned methods: mean ± half-range (max − min) / 2 over %d training seeds on the same test "
                "frames; methods without training: single values." % n, ""]
    e1 = read_csv(os.path.join(d, "exp1_recognition.csv"))
    if e1:
        paired = None
        for s in OrderedDict.fromkeys(r["scenario"] for r in e1):  # default, then the "any" heading scene
            rs = [r for r in e1 if r["scenario"] == s]
            out += ["### Experiment 1 (%s): accuracy" % s, "", pivot(rs, "method", "accuracy"), "",
                    "### Experiment 1 (%s): macro-F1" % s, "", pivot(rs, "method", "macro_f1"), ""]
            if any(r["method"] == "SemS" for r in rs) and any(claims.hand_pattern(r["method"]) for r in rs):
                if paired is None:  # one family over both scenes
                    paired = claims.learned_vs_hand_exp1(d, boots, seed)
                    if None in paired:
                        print("plot_results: %s" % paired[None], file=sys.stderr)
                out += ["### Experiment 1 (%s): the learned mask against the best hand pattern" % s, "",
                        paired.get(s) or paired.get(None) or "*No paired test: no kept series of this scene.*", ""]
    e3 = read_csv(os.path.join(d, "exp3_conditions.csv"))
    if e3:
        for s in ("no_md", "clutter"):
            rs = [r for r in e3 if r["scenario"] == s]
            if rs:
                out += ["### Experiment 3 (%s): accuracy" % s, "", pivot(rs, "method", "accuracy"), ""]
    e4 = read_csv(os.path.join(d, "exp4_delay.csv"))
    if e4:
        for s in ("single", "multipath"):
            rs = [r for r in e4 if r["scenario"] == s]
            if rs:
                out += ["### Experiment 4 (%s): delay-index MAE" % s, "", pivot(rs, "method", "mae_index", "%.3g"), ""]
    e5 = read_csv(os.path.join(d, "exp5_pilot_budget.csv"))
    if e5:
        out += ["### Experiment 5: SemS delay-index MAE by pilot budget (multipath)", "",
                pivot(e5, "n_pilots", "mae_index", "%.3g"), ""]
    e6 = read_csv(os.path.join(d, "exp6_cost.csv"))
    if e6:
        out += ["### Experiment 6: cost (inference time per frame, this machine) next to the result", "",
                "| experiment | scenario | method | N_p | SNR (dB) | metric | value | us/frame | training (s) |",
                "|---|---|---|---|---|---|---|---|---|"]
        # One line per method and operating point; over training seeds the value is
        # mean ± half-range, the times are means.
        groups = OrderedDict()
        for r in e6:
            if fnum(r["snr_db"]) in (10.0, 30.0):
                k = (r["experiment"], r["scenario"], r["method"], r.get("mask", ""), r["n_pilots"], r["snr_db"],
                     r["metric"])
                groups.setdefault(k, []).append(r)
        names = {}
        for k in OrderedDict.fromkeys(k[:2] for k in groups):  # a method on several masks is named with its mask
            names[k] = labels([r for r in e6 if (r["experiment"], r["scenario"]) == k])
        for k, rs in groups.items():
            row = k[:2] + (names[k[:2]][(k[2], k[3])],) + k[4:]
            out.append("| %s | %s | %s | %s | %s | %s | %s | %.3g | %.3g |" % (row + (
                cell([fnum(r["value"]) for r in rs], "%.3g"),
                over_seeds([fnum(r["us_per_frame"]) for r in rs])[0],
                over_seeds([fnum(r["train_seconds"]) for r in rs])[0])))
        out.append("")
    return "\n".join(out)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="directory with sems_eval's CSVs")
    ap.add_argument("--out", help="where to write the PNGs (default: the results directory)")
    ap.add_argument("--tsne-iter", type=int, default=500, help="t-SNE iterations")
    ap.add_argument("--tables", help="also write the result tables as markdown to this file")
    ap.add_argument("--bootstrap", type=int, default=claims.BOOTSTRAP,
                    help="bootstrap resamples of the paired tables (default %d)" % claims.BOOTSTRAP)
    a = ap.parse_args(argv)
    if a.bootstrap < 100:
        print("plot_results: --bootstrap must be >= 100, got %d" % a.bootstrap, file=sys.stderr)
        return 2
    if not os.path.isdir(a.results):
        print("plot_results: %s is not a directory" % a.results, file=sys.stderr)
        return 1
    out = a.out or a.results
    os.makedirs(out, exist_ok=True)
    made = [p for p in (exp1(a.results, out), exp2(a.results, out, a.tsne_iter), exp3(a.results, out),
                        exp4(a.results, out), exp5(a.results, out), exp6(a.results, out)) if p]
    if not made:
        print("plot_results: no sems_eval CSVs in %s" % a.results, file=sys.stderr)
        return 1
    for p in made:
        print("wrote", p)
    if a.tables:
        with open(a.tables, "w") as f:
            f.write(tables(a.results, a.bootstrap))
        print("wrote", a.tables)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
