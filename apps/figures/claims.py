#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The claims of docs/RESULTS.md tested pairwise on the kept per-frame predictions.

    /usr/bin/python3 apps/figures/claims.py docs/results                 # writes docs/results/claims.md
    /usr/bin/python3 apps/figures/claims.py RESULTS --out FILE [--bootstrap B] [--seed S]
    (each family's tests: experiments 1-5 on the page, experiment 7's on a second page beside it,
    FILE's name with _kinematic: docs/results/claims_kinematic.md)
    /usr/bin/python3 apps/figures/claims.py RESULTS --only "MSE-DL"      # the claims whose text has it, printed

Reads the kept predictions of experiments 1, 3, 4, 5 and 7 in RESULTS (<csv stem>_predictions.npz
and exp<N>_truth.npz, written by sems_eval beside its CSVs; apps/figures/predictions.py reads
them) and, for the single-path bound, exp4_delay.csv's CRB rows. Each claim is one family of
paired tests (apps/figures/paired_stats.py): per SNR (and scene or pilot budget) the difference
of two methods on the same test frames and training seeds, its two-level bootstrap SE, its
p-value, Holm's correction over the family, and the verdict at 0.05. A claim whose predictions
are missing says which file is missing and which command writes it.

The same comparisons make the paired tables of plot_results.py (experiment 1: the learned mask
against the best hand pattern) and plot_kinematic.py (experiment 7: against the best hand
pattern, by pilot budget, learned energies, template banks): learned_vs_hand_exp1() and
exp7_tables() here.
"""
import argparse
import csv
import os
import sys
from collections import OrderedDict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paired_stats as ps  # noqa: E402
import predictions as kp  # noqa: E402

BOOTSTRAP = 2000
SEED = 1
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Families shared by the claims page and the tables of plot_results.py and plot_kinematic.py:
# the same tests under the same name, whichever page shows them.
EXP1_HAND = "experiment 1: the learned mask against the best hand pattern, every scene and SNR"
EXP7_HAND = "experiment 7: the learned mask against the best hand pattern, every N_p and SNR"
EXP7_ENERGIES = "experiment 7: learned pilot energies against equal energies, every N_p and SNR"
EXP7_BANK = "experiment 7: with template banks, the learned mask against the Doppler pattern, every N_p and SNR"


def hand_pattern(method):
    """A hand pattern under the SemS decoder ("SemS decoder (doppler pilots)"), not with a bank."""
    return method.startswith("SemS decoder (") and method.endswith(" pilots)")


def short(method):
    """A hand pattern's name ("doppler"), any other method's as it is."""
    return method[len("SemS decoder ("):-len(" pilots)")] if hand_pattern(method) else method


def name_of(exp, scenario, method, mask):
    """A method's name, with its mask where the method runs on several in the scene."""
    masks = {k[2] for k in exp.keys(scenario) if k[1] == method}
    return method if len(masks) <= 1 else "%s (%s)" % (method, mask)


def picked(exp, scenario, pick):
    """rivals() for Comparison: every (method, mask) of the scene that pick(method) keeps, at the
    first method's SNR and N_p (a method on the full grid, Perfect CSI, at its own)."""
    def rivals(np_, snr, sa):
        found = OrderedDict()
        for k in exp.keys(scenario):
            if pick(k[1]):
                found.setdefault((k[1], k[2]), set()).add(k[3])
        out = []
        for (m, mask), budgets in found.items():
            at = np_ if np_ in budgets else (next(iter(budgets)) if mask == "full grid" and len(budgets) == 1 else None)
            if at is not None:
                out.append((name_of(exp, scenario, m, mask), exp.scores(scenario, m, at, snr, mask)))
        return out
    return rivals


class Comparison:
    """The tests of one method against a rival (or the best of several rivals, at each point)
    at each N_p of budgets and each SNR of the scene, added to `family`. rivals(np_, snr, sa)
    gives [(name, {seed: scores})]; rows() gives the tests with the family's verdicts."""

    def __init__(self, family, exp, label, scenario, first, rivals, budgets, boots=BOOTSTRAP, seed=SEED):
        self.family, self.exp, self.label, self.scenario, self.first = family, exp, label, scenario, first
        self.points = []  # (n_pilots, snr, rival's name, index in the family)
        snrs = sorted({k[4] for k in exp.keys(scenario)})
        mean = lambda s: sum(v.mean() for v in s.values()) / len(s)  # noqa: E731
        for np_ in budgets:
            for snr in snrs:
                sa = exp.scores(scenario, first, np_, snr)
                cands = [(n, sb) for n, sb in rivals(np_, snr, sa) if sb] if sa else []
                if not cands:
                    continue
                # The best rival by its mean over seeds and frames at this point: a choice in its favour.
                best = (min if exp.lower_is_better else max)(cands, key=lambda c: mean(c[1]))
                key = (exp.experiment, scenario, first, best[0], np_, snr)
                r = ps.compare(sa, best[1], ps.rng_for(seed, key), boots)
                if r is not None:
                    self.points.append((np_, snr, best[0], len(family)))
                    family.add(key, r)

    def rows(self, n_pilots=None):
        """[(n_pilots, snr, rival, result, Holm p, verdict)], at one N_p when given."""
        res = self.family.results()
        return [(np_, snr, rival) + tuple(res[i][1:]) for np_, snr, rival, i in self.points
                if n_pilots is None or np_ == n_pilots]


def fmt_diff(r, lower):
    return ("%+.3g ± %.2g" if lower else "%+.3f ± %.3f") % (r["diff"], r["se"])


def fmt_p(p):
    return "< 1e-300" if p == 0 else "%.2g" % p


def fmt_mean(v, lower):
    return "%.3g" % v if lower else "%.3f" % v


MARK = {"ahead": "**ahead**", "behind": "**behind**", "tied": "tied"}


def paired_text(comp, first_label, rival_label, boots=BOOTSTRAP):
    """Markdown: how a comparison's tables are made, naming its family and the correction."""
    rows = comp.rows()
    if not rows:
        return ""
    fam = comp.family
    r0 = rows[0][3]
    seeds = r0["seeds"] if isinstance(r0["seeds"], int) else "%d and %d" % r0["seeds"]
    return ("Paired on the same %d test frames and %s training seed(s): the difference of mean %s (%s minus %s) "
            "± its two-level bootstrap SE (%d resamples of seeds and frames), its two-sided p (normal "
            "approximation) and the p adjusted over the %s. **ahead**/**behind**: adjusted p below %g%s." % (
                r0["n"], seeds, "absolute error" if fam.lower_is_better else "accuracy", first_label, rival_label,
                boots, fam.describe(), fam.alpha,
                "; the hand pattern tested is the one with the best mean at that point (a choice in its favour)"
                if rival_label.startswith("best") else ""))


def paired_table(comp, first_label, rival_label, n_pilots=None, boots=BOOTSTRAP, text=True):
    """Markdown: the tests of a comparison (at one N_p when given), after paired_text() unless
    text is False."""
    rows = comp.rows(n_pilots)
    if not rows:
        return None
    lower = comp.family.lower_is_better
    out = [paired_text(comp, first_label, rival_label, boots), ""] if text else []
    out += ["| SNR (dB) | %s | %s | difference ± SE | p | Holm p | verdict |" % (first_label, rival_label),
            "|---|---|---|---|---|---|---|"]
    for np_, snr, rival, r, adj, v in rows:
        which = " (%s)" % short(rival) if rival_label.startswith("best") else ""
        out.append("| %g | %s | %s%s | %s | %s | %s | %s |" % (
            snr, fmt_mean(r["a"], lower), fmt_mean(r["b"], lower), which, fmt_diff(r, lower), fmt_p(r["p"]),
            fmt_p(adj), MARK[v]))
    return "\n".join(out)


def missing_note(err):
    return "*Paired table not available: %s*" % err


# ---------------------------------------------------------------- experiment 1 and 7 tables

def learned_vs_hand_exp1(results, boots=BOOTSTRAP, seed=SEED):
    """{scene: markdown} of experiment 1: SemS against the best hand pattern, one family over
    both scenes and every SNR; {None: note} when the kept predictions are missing."""
    exp = kp.Experiment(results, "1")
    try:
        exp.require("exp1_recognition")
    except kp.Missing as e:
        return {None: missing_note(e)}
    fam = ps.Family(EXP1_HAND)
    comps = OrderedDict((s, Comparison(fam, exp, s, s, "SemS", picked(exp, s, hand_pattern), [32], boots, seed))
                        for s in exp.truth.scenarios)
    return OrderedDict((s, paired_table(c, "SemS (learned)", "best hand pattern", boots=boots))
                       for s, c in comps.items() if c.points)


def exp7_tables(results, boots=BOOTSTRAP, seed=SEED):
    """Experiment 7's paired tables: {"hand": {N_p: markdown}} (one family over every N_p and
    SNR), {"energies": {N_p: markdown}}, {"bank": {N_p: markdown}} (a family each), each table
    without the text that explains it, which is "<part>_text". A part whose kept file is missing
    gets {None: a note naming the file and the command}; "hand_note" notes the budget parts
    missing beside the main one."""
    out = {}
    exp = kp.Experiment(results, "7")
    scen = "kinematic"
    for part, stems, first, pick, first_label, rival_label, title in (
            ("hand", ("exp7_kinematic",), "SemS", hand_pattern, "SemS (learned)", "best hand pattern",
             EXP7_HAND),
            ("energies", ("exp7_pilot_power", "exp7_kinematic"), "SemS (learned energies)", lambda m: m == "SemS",
             "SemS (learned energies)", "SemS",
             EXP7_ENERGIES),
            ("bank", ("exp7_bank",), "SemS + template bank",
             lambda m: m == "SemS decoder + template bank (doppler pilots)", "SemS + template bank",
             "Doppler pattern + template bank",
             EXP7_BANK)):
        try:
            exp.require(*stems)
        except kp.Missing as e:
            out[part] = {None: missing_note(e)}
            continue
        budgets = sorted({k[3] for k in exp.keys(scen) if k[1] == first})
        comp = Comparison(ps.Family(title), exp, "", scen, first, picked(exp, scen, pick), budgets, boots, seed)
        out[part] = OrderedDict((n, paired_table(comp, first_label, rival_label, n, boots, text=False))
                                for n in budgets if comp.rows(n))
        out[part + "_text"] = paired_text(comp, first_label, rival_label, boots)
    out["hand_note"] = " ".join(missing_note(exp.missing[s]) for s in ("exp7_pilot_budget", "exp7_burst")
                                if s in exp.missing and "exp7_kinematic" not in exp.missing)
    return out


# ---------------------------------------------------------------- the claims page

def crb_rival(results, scenario, n_frames):
    """rivals() for the single-path bound: the CRB's MAE of each seed's SemS pilots (one number
    per mask and SNR, exp4_delay.csv) on every frame."""
    path = os.path.join(results, "exp4_delay.csv")
    rows = []
    if os.path.exists(path):
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["method"] == "CRB" and r["mask"] == "SemS pilots"
                    and r["scenario"] == scenario]

    def rivals(np_, snr, sa):
        crb = OrderedDict((r["train_seed"], kp.np.full(n_frames, float(r["mae_index"]))) for r in rows
                          if int(r["n_pilots"]) == np_ and float(r["snr_db"]) == snr and r["train_seed"] in sa)
        return [("CRB of its pilots", crb)]
    return rivals


def budget_step(exp, scenario, method, lower):
    """rivals() of one method against itself at another pilot budget `lower`."""
    def rivals(np_, snr, sa):
        return [("%s, N_p %d" % (method, lower), exp.scores(scenario, method, lower, snr))]
    return rivals


# One claim: its text (docs/RESULTS.md, "The paper's claims", and experiment 7's readings), the
# kept files it needs, its family's name, and its comparisons: (experiment, label, scene, first
# method, rivals: "crb", "budget steps", or pick(method) of the rivals, budgets: "32" or "all").
CLAIMS = [
    ("SemS beats reconstruction-trained pilots (MSE-DL)", ["exp1_recognition"], "SemS against MSE-DL",
     [("1", "experiment 1, %s" % s, s, "SemS", lambda m: m == "MSE-DL", "32") for s in ("default", "any")]),
    ("SemS beats the feature SVM", ["exp1_recognition", "exp3_conditions"], "SemS against the best feature SVM",
     [("1", "experiment 1, %s" % s, s, "SemS", lambda m: m.startswith("SVM"), "32") for s in ("default", "any")] +
     [("3", "experiment 3, %s" % s, s, "SemS", lambda m: m.startswith("SVM"), "32") for s in ("no_md", "clutter")]),
    ("SemS comes close to perfect CSI", ["exp1_recognition"], "SemS against Perfect CSI",
     [("1", "experiment 1, default", "default", "SemS", lambda m: m == "Perfect CSI (test SNR)", "32"),
      ("1", "experiment 1, default", "default", "SemS", lambda m: m == "Perfect CSI (noiseless)", "32")]),
    ("learned pilots beat hand-made ones (experiment 1)", ["exp1_recognition"], EXP1_HAND,
     [("1", "experiment 1, %s" % s, s, "SemS", hand_pattern, "32") for s in ("default", "any")]),
    ("learned pilots beat hand-made ones (experiment 7, by pilot budget)",
     ["exp7_kinematic", "exp7_pilot_budget", "exp7_burst"], EXP7_HAND,
     [("7", "experiment 7", "kinematic", "SemS", hand_pattern, "all")]),
    ("learned pilots beat hand-made ones (experiment 7, each decoder with a template bank)", ["exp7_bank"], EXP7_BANK,
     [("7", "experiment 7", "kinematic", "SemS + template bank",
       lambda m: m == "SemS decoder + template bank (doppler pilots)", "all")]),
    ("robust to clutter", ["exp3_conditions"], "under clutter: SemS against MSE-DL and the best SVM",
     [("3", "experiment 3, clutter", "clutter", "SemS", lambda m: m == "MSE-DL", "32"),
      ("3", "experiment 3, clutter", "clutter", "SemS", lambda m: m.startswith("SVM"), "32")]),
    ("without micro-Doppler the SVM comes close", ["exp3_conditions"],
     "without micro-Doppler: SemS against the best SVM",
     [("3", "experiment 3, no_md", "no_md", "SemS", lambda m: m.startswith("SVM"), "32")]),
    ("multipath delay error far below the classical methods", ["exp4_delay"],
     "multipath delay: SemS against the best classical estimator",
     [("4", "experiment 4, multipath", "multipath", "SemS",
       lambda m: not m.startswith(("SemS", "Shipped", "CRB")), "32")]),
    ("single-path delay near the bound", ["exp4_delay"],
     "single-path delay: SemS's mean absolute error against the CRB of its own pilots",
     [("4", "experiment 4, single", "single", "SemS", "crb", "32")]),
    ("two pilots fail, large budgets saturate", ["exp5_pilot_budget"],
     "experiment 5: SemS at a pilot budget against the budget below it",
     [("5", "experiment 5", "multipath", "SemS", "budget steps", "all")]),
    ("learned pilot energies tie equal ones (experiment 7)", ["exp7_pilot_power", "exp7_kinematic"], EXP7_ENERGIES,
     [("7", "experiment 7", "kinematic", "SemS (learned energies)", lambda m: m == "SemS", "all")]),
    ("SemS beats MSE-DL and the feature SVMs on moving scatterers (experiment 7)", ["exp7_kinematic"],
     "experiment 7: SemS against MSE-DL and the best SVM",
     [("7", "experiment 7", "kinematic", "SemS", lambda m: m == "MSE-DL", "32"),
      ("7", "experiment 7", "kinematic", "SemS", lambda m: m.startswith("SVM"), "32")]),
    ("Perfect CSI is a reference, not a bound (experiment 7)", ["exp7_kinematic"],
     "experiment 7: SemS and SemS + template bank against Perfect CSI at the test SNR",
     [("7", "experiment 7", "kinematic", m, lambda r: r == "Perfect CSI (test SNR)", "32")
      for m in ("SemS", "SemS + template bank")]),
    ("a decoder that keeps its training frames gains (experiment 7)", ["exp7_kinematic"],
     "experiment 7: SemS + template bank against SemS",
     [("7", "experiment 7", "kinematic", "SemS + template bank", lambda m: m == "SemS", "32")]),
]


def experiment_of(stem):
    return stem[3:stem.index("_")]


def comparisons_of(claim, pools, results, fam, boots, seed):
    """The claim's comparisons (Comparison objects with tests in fam)."""
    comps = []
    for e, label, scen, first, rivals, budgets in claim[3]:
        exp = pools[e]
        if exp.truth is None or scen not in exp.truth.scenarios:
            continue
        have = sorted({k[3] for k in exp.keys(scen) if k[1] == first})
        if rivals == "crb":
            comps.append(Comparison(fam, exp, label, scen, first, crb_rival(results, scen, exp.truth.scenarios[scen][1]),
                                    [32], boots, seed))
        elif rivals == "budget steps":  # each N_p against the one below it
            for lo, hi in zip(have, have[1:]):
                comps.append(Comparison(fam, exp, "%s, N_p %d against %d" % (label, hi, lo), scen, first,
                                        budget_step(exp, scen, first, lo), [hi], boots, seed))
        else:
            for np_ in (have if budgets == "all" else [32]):
                comps.append(Comparison(fam, exp, "%s, N_p %d" % (label, np_) if budgets == "all" else label, scen,
                                        first, picked(exp, scen, rivals), [np_], boots, seed))
    return [c for c in comps if c.points]


def kinematic_page_name(page):
    """The second page's file name beside `page` (experiment 7's families' tests)."""
    stem, ext = os.path.splitext(os.path.basename(page))
    return stem + "_kinematic" + (ext or ".md")


def claims_page(results, boots=BOOTSTRAP, seed=SEED, only=None, command=None, page_dir=None,
                kinematic_name="claims_kinematic.md", main_name="claims.md"):
    """The claims page and experiment 7's families' page (markdown, their links relative to
    page_dir, default RESULTS; the second is kinematic_name beside the first), the messages of the
    missing kept files, and how many claims were tested. Two pages keep each one readable: every
    family's table lists every test it corrects for."""
    pools = OrderedDict((e, kp.Experiment(results, e)) for e in kp.SOURCES)
    summary, details, details7, missing = [], [], [], OrderedDict()
    tested = 0
    for claim in CLAIMS:
        text, stems, family_name = claim[0], claim[1], claim[2]
        if only and only.lower() not in (text + " " + family_name).lower():
            continue
        gaps = [pools[experiment_of(s)].missing[s] for s in stems if s in pools[experiment_of(s)].missing]
        if gaps:
            for m in gaps:
                missing[m] = None
            files = [s + "_predictions.npz" for s in stems if s in pools[experiment_of(s)].missing]
            summary.append("| %s | — | — | — | — | not tested: %s missing (below) | %s |" % (
                text, ", ".join("`%s`" % f for f in files), family_name))
            continue
        lower = experiment_of(stems[0]) in ("4", "5")
        fam = ps.Family(family_name, lower_is_better=lower)
        comps = comparisons_of(claim, pools, results, fam, boots, seed)
        if not comps:
            summary.append("| %s | %s | — | — | — | no series to compare in the kept predictions | — |" % (
                text, family_name))
            continue
        tested += 1
        print("claims.py: %s: %d tests" % (family_name, len(fam)), flush=True)
        for c in comps:
            rows = c.rows()
            rivals = list(OrderedDict.fromkeys(r[2] for r in rows))
            verdicts = OrderedDict()
            for r in rows:
                verdicts.setdefault(r[5], []).append("%g" % r[1])
            verdict = ("%s at every SNR" % rows[0][5] if len(verdicts) == 1 else
                       "; ".join("%s at %s dB" % (v, ", ".join(s)) for v, s in verdicts.items()))
            summary.append("| %s | %s against %s (%s) | %s | %s | %s | %s | %s (%d tests) |" % (
                text, c.first, rivals[0] if len(rivals) == 1 else "the best of " + ", ".join(short(r) for r in rivals),
                c.label, ", ".join("%g" % r[1] for r in rows),
                "; ".join("%g: %s" % (r[1], fmt_diff(r[3], lower)) for r in rows),
                fmt_p(max(r[4] for r in rows)), verdict, fam.name, len(fam)))
        into = details7 if experiment_of(stems[0]) == "7" else details
        into += ["", "### %s" % fam.name, "",
                    "Claim: *%s*. The %s." % (text, fam.describe()), "",
                    "| comparison | SNR (dB) | %s | rival | rival's | difference ± SE | p | Holm p | verdict |" % (
                        "mean abs. error" if lower else "accuracy"),
                    "|---|---:|---:|---|---:|---:|---:|---:|---|"]
        for c in comps:
            for np_, snr, rival, r, adj, v in c.rows():
                into.append("| %s: %s | %g | %s | %s | %s | %s | %s | %s | %s |" % (
                    c.label, c.first, snr, fmt_mean(r["a"], lower), rival, fmt_mean(r["b"], lower),
                    fmt_diff(r, lower), fmt_p(r["p"]), fmt_p(adj), MARK[v]))
    command = command or "/usr/bin/python3 apps/figures/claims.py %s" % os.path.relpath(results)
    out = ["# The paper's claims, tested on paired predictions", "",
           "Generated by `%s` from the per-frame predictions that `sems_eval` keeps beside its CSVs "
           "(`*_predictions.npz`, `exp*_truth.npz`: [file formats](%s)), %d bootstrap resamples, seed %d."
           % (command, os.path.relpath(os.path.join(ROOT, "docs", "reference", "file_formats.md"), page_dir or results)
              + "#kept-predictions-_predictionsnpz-expn_truthnpz--appsevaluationsems_evalpredictionsh", boots, seed), "",
           "Each row compares two methods on the same test frames: the difference of their mean accuracy (for "
           "delays, of their mean absolute delay-index error, so that a negative difference is the first method "
           "better) over the training seeds and test frames, ± its standard error from a two-level paired "
           "bootstrap (the training seeds resampled with replacement, and the test frames with replacement, the "
           "same frame indices for both methods and every seed; a method without training pairs with every seed "
           "of the other). The p-value is two-sided, from the difference over that SE (normal approximation: the "
           "bootstrap's own tail fraction cannot resolve p-values below one over the resamples, smaller than "
           "Holm's thresholds need). Each claim is one family: Holm's step-down correction runs over all its "
           "tests (every scene, pilot budget and SNR it covers), and a test is **ahead** or **behind** only if "
           "its adjusted p is below %g, else tied. Where a method meets the best of several rivals, the one with "
           "the best mean at that point is tested, a choice in the rival's favour. The seed level of the "
           "bootstrap draws from the training seeds there are (three in the documented runs), so the spread "
           "between trainings in the SE is estimated from those." % ps.ALPHA, "",
           "## Summary", "",
           "| claim | comparison | SNR (dB) | difference ± SE (dB: value) | largest Holm p | verdict | family |",
           "|---|---|---|---|---|---|---|"] + summary
    if details or details7:
        out += ["", "## Each family's tests"] + details
    if details7:
        out += ["", "Experiment 7's families: [%s](%s)." % (kinematic_name, kinematic_name)]
    if missing:
        out += ["", "## Missing kept predictions", ""] + ["- %s" % m for m in missing]
    out += ["", "Not tested here: *the SemS features separate the classes* (experiment 2 is a picture of the "
            "features, with no paired outcome per frame)."]
    page7 = None
    if details7:
        page7 = "\n".join(["# The paper's claims on moving scatterers (experiment 7): each family's tests", "",
                           "Generated by `%s` with [%s](%s), whose introduction gives the method and "
                           "whose summary gives every verdict." % (command, main_name, main_name)]
                          + details7) + "\n"
    return "\n".join(out) + "\n", page7, list(missing), tested


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="folder with the CSVs and the kept predictions (e.g. docs/results)")
    ap.add_argument("--out", help="the page to write (default RESULTS/claims.md)")
    ap.add_argument("--bootstrap", type=int, default=BOOTSTRAP, help="bootstrap resamples (default %d)" % BOOTSTRAP)
    ap.add_argument("--seed", type=int, default=SEED, help="seed of the bootstrap (default %d)" % SEED)
    ap.add_argument("--only", help="only the claims whose text or family has this (printed, not written)")
    a = ap.parse_args(argv)
    if a.bootstrap < 100:
        print("claims.py: --bootstrap must be >= 100, got %d" % a.bootstrap, file=sys.stderr)
        return 2
    if not os.path.isdir(a.results):
        print("claims.py: %s is not a directory" % a.results, file=sys.stderr)
        return 2
    try:
        out = a.out or os.path.join(a.results, "claims.md")
        command = "/usr/bin/python3 apps/figures/claims.py %s" % os.path.relpath(a.results)
        if a.bootstrap != BOOTSTRAP or a.seed != SEED:
            command += " --bootstrap %d --seed %d" % (a.bootstrap, a.seed)
        out7 = os.path.join(os.path.dirname(out), kinematic_page_name(out))
        page, page7, missing, tested = claims_page(a.results, a.bootstrap, a.seed, a.only, command,
                                                   os.path.dirname(os.path.abspath(out)), os.path.basename(out7),
                                                   os.path.basename(out))
    except ValueError as e:  # kept files that do not fit together
        print("claims.py: %s" % e, file=sys.stderr)
        return 1
    for m in missing:
        print("claims.py: %s" % m, file=sys.stderr)
    if a.only:
        print(page + (page7 or ""))
        return 0
    with open(out, "w") as f:
        f.write(page)
    if page7:
        with open(out7, "w") as f:
            f.write(page7)
    elif os.path.exists(out7):  # a page of an earlier run's experiment 7, whose predictions are gone
        os.remove(out7)
        print("claims.py: removed %s (no experiment 7 predictions in %s)" % (out7, a.results))
    print("claims.py: wrote %s%s (%d families tested%s)" % (
        out, " and " + out7 if page7 else "", tested, ", %d kept files missing" % len(missing) if missing else ""))
    return 0 if tested else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
