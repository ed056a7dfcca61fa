#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""End-to-end: sems_eval --size test --seeds 2 writes the seven experiments' CSVs (every learned
method once per training seed, on the same test frames) and, beside those of experiments 1, 3, 4,
5 and 7, every method's per-frame predictions and the test frames' truth, from which every
score is recomputed exactly; plot_results.py and plot_kinematic.py draw one PNG per experiment
and the tables from them, with paired tests on the kept predictions, and claims.py the claims
page; the paired statistics (apps/figures/paired_stats.py) against closed forms; bad options
fail clearly.

CTest runs it with the staged package and the build and source folders in the environment;
by hand: SEMS_BUILD_DIR=build PYTHONPATH=build/python_pkg /usr/bin/python3 python/sems/qa/qa_sems_eval.py
(the build folder defaults to <source>/build)."""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from gnuradio import gr_unittest

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
BUILD = os.environ.get("SEMS_BUILD_DIR", os.path.join(SOURCE, "build"))
EVAL = os.path.join(BUILD, "apps", "sems_eval")
FIGURES = os.path.join(SOURCE, "apps", "figures")
PLOT = os.path.join(SOURCE, "apps", "figures", "plot_results.py")

CSVS = {
    "exp1_recognition.csv": ["method", "snr_db", "accuracy", "macro_f1", "n_frames", "seed", "train_seed",
                             "us_per_frame"],
    "exp2_tsne_features.csv": ["method", "class_id", "f0", "f15"],
    "exp3_conditions.csv": ["scenario", "method", "snr_db", "accuracy", "n_frames", "seed", "train_seed",
                            "us_per_frame"],
    "exp4_delay.csv": ["scenario", "method", "snr_db", "mae_index", "crb_mae_index", "n_frames", "seed",
                       "train_seed", "us_per_frame"],
    "exp5_pilot_budget.csv": ["n_pilots", "snr_db", "mae_index", "n_frames", "seed", "train_seed", "us_per_frame"],
    "exp6_cost.csv": ["method", "snr_db", "metric", "value", "us_per_frame", "n_frames", "seed", "train_seed"],
    "exp7_kinematic.csv": ["method", "mask", "n_pilots", "snr_db", "accuracy", "macro_f1", "n_frames", "seed",
                           "train_seed", "us_per_frame"],
    "exp7_confusion.csv": ["method", "snr_db", "train_seed", "true_class", "predicted_class", "count"],
    "exp7_pilot_budget.csv": ["method", "mask", "n_pilots", "snr_db", "accuracy", "n_frames", "seed", "train_seed"],
    "exp7_pilot_power.csv": ["method", "mask", "n_pilots", "snr_db", "accuracy", "n_frames", "seed", "train_seed"],
    "exp7_bank.csv": ["method", "mask", "n_pilots", "snr_db", "accuracy", "n_frames", "seed", "train_seed"],
    "exp7_burst.csv": ["method", "mask", "n_pilots", "snr_db", "accuracy", "n_frames", "seed", "train_seed"],
}
PLOT7 = os.path.join(SOURCE, "apps", "figures", "plot_kinematic.py")
CLAIMS = os.path.join(FIGURES, "claims.py")
KEPT = os.path.join(FIGURES, "predictions.py")
# The CSVs of each experiment with kept predictions (<stem>_predictions.npz; exp<N>_truth.npz).
KEPT_STEMS = {"1": ["exp1_recognition"], "3": ["exp3_conditions"], "4": ["exp4_delay"], "5": ["exp5_pilot_budget"],
              "7": ["exp7_kinematic", "exp7_pilot_budget", "exp7_pilot_power", "exp7_bank", "exp7_burst"]}
KINEMATIC = ["adult", "bicyclist", "car", "child", "hexacopter", "quadcopter"]
SEED = 2026  # sems_eval's default --seed: the training seeds are SEED and SEED + 1
TRAIN_SEEDS = {str(SEED), str(SEED + 1)}


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_kept(path):
    """A kept-predictions file read as docs/reference/file_formats.md describes it, with numpy
    alone (not through apps/figures/predictions.py): (info, series, values), values one row per
    series (class ids, -1 = none; or float32 delay errors); the packed rows' padding is checked."""
    with np.load(path, allow_pickle=False) as z:
        info, series, raw = z["info"][0], z["series"], z["values"]
    n, b = int(info["n_frames"]), int(info["bits"])
    if str(info["quantity"]) == "class_id":
        assert raw.dtype == np.uint8 and raw.shape == (len(series), (n * b + 7) // 8), (raw.dtype, raw.shape)
        bits = np.unpackbits(raw, axis=1)
        assert not bits[:, n * b:].any(), "padding bits must be zero"
        values = (bits[:, :n * b].reshape(len(series), n, b) * (1 << np.arange(b - 1, -1, -1))).sum(axis=2) - 1
    else:
        assert raw.dtype == np.float32 and raw.shape == (len(series), n), (raw.dtype, raw.shape)
        values = raw
    return info, series, values


def series_rows(series):
    """Kept series as CSV-like rows (the CSVs' spelling of SNR and training seed)."""
    return [{"scenario": str(s["scenario"]), "method": str(s["method"]), "mask": str(s["mask"]),
             "n_pilots": str(int(s["n_pilots"])), "snr_db": "%g" % s["snr_db"],
             "train_seed": str(int(s["train_seed"])) if s["train_seed"] >= 0 else "none"} for s in series]


def csv6(v):
    """A float as sems_eval writes it (6 significant digits, inf and nan spelled out)."""
    return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else "%.6g" % v


def recognition_scores(pred, truth, n_classes):
    """Accuracy and macro-F1 with sems_eval's operations in its order (common.cc, score())."""
    tp, fp, fn = [0.0] * n_classes, [0.0] * n_classes, [0.0] * n_classes
    correct = 0
    for p, t in zip(pred, truth):
        if p == t:
            correct += 1
            tp[t] += 1
        else:
            if 0 <= p < n_classes:
                fp[p] += 1
            fn[t] += 1
    f1, present = 0.0, 0
    for k in range(n_classes):
        if tp[k] + fn[k] > 0:
            present += 1
            d = 2 * tp[k] + fp[k] + fn[k]
            f1 += 2 * tp[k] / d if d > 0 else 0.0
    return correct / len(truth), f1 / present if present else 0.0


def delay_scores(err):
    """MAE, RMSE, median absolute error and fraction above half an index, summed in frame order
    as sems_eval does (delay.cc, delay_errors())."""
    mae = rmse = gross = 0.0
    a = []
    for e in (float(x) for x in err):
        a.append(abs(e))
        mae += abs(e)
        rmse += e * e
        gross += 1.0 if abs(e) > 0.5 else 0.0
    return {"mae_index": mae / len(a), "rmse_index": math.sqrt(rmse / len(a)),
            "median_abs_error_index": sorted(a)[len(a) // 2], "frac_error_over_half_index": gross / len(a)}


def write_kept(path, experiment, scenario, test_seed, series, n_classes):
    """A kept class-id file in the documented format, from {(method, mask, n_pilots, snr, seed):
    ids} (for synthetic results)."""
    n = len(next(iter(series.values())))
    b = max(1, int(math.ceil(math.log2(n_classes + 1))))
    keys = list(series)
    rec = np.array([(scenario, m, mk, np_, snr, seed, test_seed) for m, mk, np_, snr, seed in keys],
                   dtype=[("scenario", "<U16"), ("method", "<U64"), ("mask", "<U32"), ("n_pilots", "<i4"),
                          ("snr_db", "<f8"), ("train_seed", "<i8"), ("test_seed", "<u8")])
    bits = np.array([[(v + 1) >> (b - 1 - k) & 1 for v in series[key] for k in range(b)] for key in keys],
                    dtype=np.uint8)
    info = np.array([("sems_eval kept predictions", 1, experiment, "class_id", b, n)],
                    dtype=[("format", "<U32"), ("version", "<i4"), ("experiment", "<U2"), ("quantity", "<U20"),
                           ("bits", "<i4"), ("n_frames", "<i4")])
    np.savez(path, info=info, series=rec, values=np.packbits(bits, axis=1))


def write_truth(path, experiment, scenario, test_seed, labels, classes):
    info = np.array([("sems_eval kept predictions", 1, experiment, "truth")],
                    dtype=[("format", "<U32"), ("version", "<i4"), ("experiment", "<U2"), ("quantity", "<U8")])
    scen = np.array([(scenario, test_seed, len(labels))], dtype=[("scenario", "<U16"), ("test_seed", "<u8"),
                                                                 ("n_frames", "<i4")])
    frames = np.array([(i, c, 10.0, 50.0, 1.0) for i, c in enumerate(labels)],
                      dtype=[("frame", "<i8"), ("class_id", "<i2"), ("delay_index", "<f8"), ("range_m", "<f8"),
                             ("velocity_mps", "<f8")])
    names = np.array(list(enumerate(classes)), dtype=[("class_id", "<i4"), ("name", "<U16")])
    np.savez(path, info=info, scenarios=scen, **{"frames_" + scenario: frames, "classes_" + scenario: names})


class qa_sems_eval(gr_unittest.TestCase):
    def test_001_test_size_end_to_end(self):
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--seeds", "2", "--out", out, "--threads", "1"],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr + r.stdout[-2000:])
            for name, cols in CSVS.items():
                path = os.path.join(out, name)
                self.assertTrue(os.path.exists(path), name)
                rs = rows(path)
                self.assertGreater(len(rs), 0, name)
                for c in cols:
                    self.assertIn(c, rs[0], "%s lacks column %s" % (name, c))
            # Every method and operating point, on the same number of frames with one seed per scene;
            # every trained method (the networks and the feature SVMs) once per training seed.
            e1 = rows(os.path.join(out, "exp1_recognition.csv"))
            hand = ["SemS decoder (%s pilots)" % p for p in ("doppler", "uniform", "random")]
            want = {"default": ["SemS", "MSE-DL", "Perfect CSI (noiseless)", "Perfect CSI (test SNR)",
                                "SVM (uniform pilots)", "SVM (doppler pilots)"] + hand,
                    "any": ["SemS", "MSE-DL", "Perfect CSI (noiseless)",
                            "SVM (uniform pilots)", "SVM (doppler pilots)"] + hand}
            for scen, ms in want.items():
                got = [r["method"] for r in e1 if r["scenario"] == scen]
                self.assertEqual(sorted(set(got)), sorted(ms), scen)
                self.assertEqual(len(got), len(ms) * 3 * 2, scen)  # every method at 3 SNR points x 2 seeds
                self.assert_per_seed([r for r in e1 if r["scenario"] == scen], ms, TRAIN_SEEDS)
            self.assertEqual({r["n_frames"] for r in e1}, {"24"})
            self.assertEqual(len({r["seed"] for r in e1}), 1)
            self.assertNotIn(e1[0]["seed"], TRAIN_SEEDS)  # test frames are not drawn with a training seed
            e3 = rows(os.path.join(out, "exp3_conditions.csv"))
            for scen in ("no_md", "clutter"):
                ms = ["SemS", "MSE-DL", "Perfect CSI (noiseless)", "SVM (uniform pilots)", "SVM (doppler pilots)"]
                if scen == "clutter":  # the SVMs also with the classical MTI in front
                    ms += ["SVM (uniform pilots, MTI)", "SVM (doppler pilots, MTI)"]
                self.assert_per_seed([r for r in e3 if r["scenario"] == scen], ms, TRAIN_SEEDS)
                self.assertEqual({r["method"] for r in e3 if r["scenario"] == scen}, set(ms), scen)
            # Under clutter every network was trained with the zero-Doppler (MTI) stage; elsewhere without.
            for name in os.listdir(os.path.join(out, "bundles")):
                if name.startswith("cls_"):
                    with open(os.path.join(out, "bundles", name, "bundle.json")) as f:
                        mti = json.load(f)["decoder"]["settings"].get("mti")
                    if mti is not None:  # the spectral classifier
                        self.assertEqual(mti, "mean" if name.startswith("cls_clutter_") else "none", name)
            self.assertEqual({(r["seed"], r["n_frames"]) for r in e3}, {(e1[0]["seed"], "24")})
            for r in e1:
                self.assertTrue(0.0 <= float(r["accuracy"]) <= 1.0)
                self.assertTrue(0.0 <= float(r["macro_f1"]) <= 1.0)
            # The noiseless upper bound does not depend on the test SNR (one network per seed).
            for scen in want:
                for seed in TRAIN_SEEDS:
                    pc = {r["accuracy"] for r in e1 if r["method"] == "Perfect CSI (noiseless)"
                          and r["scenario"] == scen and r["train_seed"] == seed}
                    self.assertEqual(len(pc), 1, (scen, seed))
            e4 = rows(os.path.join(out, "exp4_delay.csv"))
            bounds = {"single": ["CRB"],
                      "multipath": ["CRB (single path at the direct path's mean power)", "CRB (multipath, direct path)"]}
            for scen in ("single", "multipath"):
                ms = {r["method"] for r in e4 if r["scenario"] == scen}
                for m in ["SemS", "OMP", "Periodogram", "UP-MUSIC", "RP-MUSIC", "OP-MUSIC"] + bounds[scen]:
                    self.assertIn(m, ms, "%s: %s missing" % (scen, m))
                for m in bounds[scen]:  # every bound on the random pattern, at every SNR
                    self.assertEqual(len([r for r in e4 if r["scenario"] == scen and r["method"] == m
                                          and r["mask"] == "random"]), 2, (scen, m))
                rs = [r for r in e4 if r["scenario"] == scen]
                self.assertEqual(len({(r["seed"], r["n_frames"]) for r in rs}), 1, scen)
                self.assertEqual(rs[0]["n_frames"], "24")
                # SemS, and what is computed on its pilots, once per training seed (the mask is learned).
                on_sems = [r for r in rs if r["method"].startswith("SemS") or r["mask"] == "SemS pilots"]
                self.assert_per_seed(on_sems, ["SemS", "LS reference (oracle order)"] + bounds[scen], TRAIN_SEEDS,
                                     key=("method", "mask"))
                # The classical estimators and the bounds on fixed pilots: no training seed, one row
                # per method, mask and SNR point.
                fixed = [r for r in rs if r not in on_sems]
                self.assertEqual({r["train_seed"] for r in fixed}, {"none"}, scen)
                self.assertEqual(len(fixed), len({(r["method"], r["mask"], r["snr_db"]) for r in fixed}), scen)
                self.assertEqual({r["snr_db"] for r in fixed}, {"0", "30"}, scen)
            self.assertEqual(len({r["seed"] for r in e4}), 2)  # single and multipath: their own frames
            # The CRB falls by 10x in variance per 10 dB: its MAE by sqrt(1000) from 0 to 30 dB.
            crb = {float(r["snr_db"]): float(r["mae_index"]) for r in e4
                   if r["method"] == "CRB" and r["mask"] == "random" and r["scenario"] == "single"}
            self.assertAlmostEqual(crb[0.0] / crb[30.0], 1000 ** 0.5, delta=1e-3)  # CSV keeps 6 digits
            e5 = rows(os.path.join(out, "exp5_pilot_budget.csv"))
            self.assertEqual(sorted({int(r["n_pilots"]) for r in e5}), [2, 8])
            self.assertEqual(len(e5), 2 * 2 * 2)  # N_p x SNR points x seeds
            self.assert_per_seed(e5, ["SemS"], TRAIN_SEEDS, key=("method", "n_pilots"))
            multipath = {(r["seed"], r["n_frames"]) for r in e4 if r["scenario"] == "multipath"}
            self.assertEqual({(r["seed"], r["n_frames"]) for r in e5}, multipath)  # experiment 4's frames
            self.check_experiment_7(out)
            e6 = rows(os.path.join(out, "exp6_cost.csv"))
            self.assertEqual({r["train_seed"] for r in e6 if r["experiment"] == "5"}, TRAIN_SEEDS)
            self.assertEqual({r["train_seed"] for r in e6 if r["method"] == "OMP"}, {"none"})

            # A bound computed by a separate run (docs/results/classifier_bayes.py --csv) is drawn
            # and tabulated beside experiment 1 from its bound_<csv>: a single value, no seeds.
            snr = min({r["snr_db"] for r in e1}, key=float)  # a point experiment 1 has
            with open(os.path.join(out, "bound_exp1_recognition.csv"), "w") as f:
                f.write("experiment,scenario,method,mask,n_pilots,snr_db,accuracy,macro_f1,n_frames,seed,train_seed,"
                        "us_per_frame,train_seconds,model\n"
                        "1,default,Bayes classifier (bound),doppler,32,%s,0.911,0.910,30000,7,none,80,0,test\n" % snr)
            png = os.path.join(out, "png")
            tables = os.path.join(out, "tables.md")
            r = subprocess.run(["/usr/bin/python3", PLOT, out, "--out", png, "--tsne-iter", "60", "--tables", tables],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(tables) as f:
                md = f.read()
            # Learned methods: mean ± half-range over the 2 seeds; classical ones: a single value.
            self.assertIn("over 2 training seeds", md)
            semS = [l for l in md.splitlines() if l.startswith("| SemS |")]
            omp = [l for l in md.splitlines() if l.startswith("| OMP |")]
            self.assertTrue(semS and all(c.count(" ± ") == 1 for l in semS for c in l.split("|")[2:-1]), semS)
            self.assertTrue(omp and not any("±" in l for l in omp), omp)
            bound = [l for l in md.splitlines() if l.startswith("| Bayes classifier (bound) |")]
            self.assertEqual(len(bound), 2, md)  # the default scene's accuracy and macro-F1 tables
            self.assertIn("| 0.911 |", bound[0])
            self.assertIn("| 0.910 |", bound[1])
            self.assertFalse(any("±" in l for l in bound), bound)
            for name in ("exp1_recognition", "exp2_tsne", "exp3_conditions", "exp4_delay", "exp5_pilot_budget",
                         "exp6_cost"):
                p = os.path.join(png, name + ".png")
                self.assertTrue(os.path.exists(p) and os.path.getsize(p) > 1000, name)
            # The learned mask against the best hand pattern: paired on the kept predictions, one
            # family over both scenes and the 3 SNRs.
            self.assertEqual(md.count('family "experiment 1: the learned mask against the best hand pattern, every '
                                      'scene and SNR": 6 tests, Holm'), 2, md)
            self.check_kept(out, want)
            self.check_claims(out)

    def check_kept(self, out, want):
        """The kept predictions of experiments 1, 3, 4, 5 and 7: one series per CSV row but the
        bounds' (every method, pilot budget, SNR and training seed) and no other; every score
        of the CSVs recomputed exactly from them and the truth; experiment 7's confusion matrix
        recounted; `predictions.py check` agrees, and fails on a changed prediction."""
        seen = 0
        for exp, stems in KEPT_STEMS.items():
            with np.load(os.path.join(out, "exp%s_truth.npz" % exp), allow_pickle=False) as z:
                self.assertEqual((str(z["info"]["experiment"][0]), str(z["info"]["quantity"][0])), (exp, "truth"))
                scen = {str(r["scenario"]): (str(r["test_seed"]), int(r["n_frames"])) for r in z["scenarios"]}
                frames = {s: z["frames_" + s] for s in scen}
                classes = {s: [str(c) for c in z["classes_" + s]["name"]] for s in scen}
            for s, f in frames.items():
                self.assertEqual(list(f["frame"]), list(range(24)), (exp, s))
                self.assertTrue(((f["class_id"] >= 0) & (f["class_id"] < len(classes[s]))).all(), (exp, s))
            for stem in stems:
                table = [r for r in rows(os.path.join(out, stem + ".csv")) if not r["method"].startswith("CRB")]
                info, series, values = read_kept(os.path.join(out, stem + "_predictions.npz"))
                self.assertEqual((str(info["format"]), int(info["version"]), str(info["experiment"]),
                                  int(info["n_frames"])), ("sems_eval kept predictions", 1, exp, 24), stem)
                self.assertEqual(int(info["bits"]), {"4": 0, "5": 0, "7": 3}.get(exp, 2), stem)  # 3 or 6 classes
                kept = series_rows(series)
                key = lambda r: (r["scenario"], r["method"], r.get("mask", ""), r["n_pilots"], r["snr_db"],  # noqa
                                 r["train_seed"])
                if exp == "5":  # its CSV has no mask column: one mask per N_p
                    self.assertEqual({r["mask"] for r in kept}, {"learned"})
                    kept_keys = [key(dict(r, mask="")) for r in kept]
                else:
                    kept_keys = [key(r) for r in kept]
                self.assertEqual(len(set(kept_keys)), len(kept_keys), "%s: a series twice" % stem)
                self.assertEqual(sorted(kept_keys), sorted(key(r) for r in table),
                                 "%s: the kept series are not the CSV's rows" % stem)
                for s in series:  # every series on its scenario's test frames
                    self.assertEqual((str(s["test_seed"]), 24), scen[str(s["scenario"])], stem)
                at = dict(zip(kept_keys, range(len(kept_keys))))
                for r in table:
                    self.assertEqual(r["seed"], scen[r["scenario"]][0], stem)
                    v = values[at[key(r)]]
                    if exp in ("4", "5"):
                        got = delay_scores(v)
                    else:
                        acc, f1 = recognition_scores([int(x) for x in v], [int(x) for x in frames[r["scenario"]]
                                                                           ["class_id"]], len(classes[r["scenario"]]))
                        got = {"accuracy": acc, "macro_f1": f1}
                    self.assertIn("mae_index" if exp in ("4", "5") else "accuracy", r)
                    for col, value in got.items():
                        if col in r:  # experiment 5's CSV has no gross-error column
                            self.assertEqual(csv6(value), r[col], (stem, key(r), col))
                    seen += 1
                # Every method at every SNR and training seed (classical and shipped ones: none).
                if exp in ("1", "3"):
                    for s in scen:
                        ms = want[s] if exp == "1" else sorted({r["method"] for r in table if r["scenario"] == s})
                        self.assert_per_seed([r for r in kept if r["scenario"] == s], ms, TRAIN_SEEDS)
                        self.assertEqual({r["snr_db"] for r in kept if r["scenario"] == s}, {"-10", "10", "30"})
                elif exp in ("4", "5"):
                    trained = [r for r in kept if r["train_seed"] != "none"]
                    self.assert_per_seed(trained, ["SemS"], TRAIN_SEEDS, key=("method", "scenario", "mask", "n_pilots"))
                    if exp == "4":
                        for s in ("single", "multipath"):
                            fixed = {r["method"] for r in kept if r["scenario"] == s and r["train_seed"] == "none"}
                            self.assertTrue({"OMP", "Periodogram", "UP-MUSIC", "RP-MUSIC", "OP-MUSIC"} <= fixed, s)
                else:
                    self.assert_per_seed(kept, sorted({r["method"] for r in table}), TRAIN_SEEDS,
                                         key=("method", "n_pilots"))
                # A noiseless method's predictions do not depend on the test SNR.
                for seed in TRAIN_SEEDS:
                    pc = [values[i] for i, r in enumerate(kept) if r["method"] == "Perfect CSI (noiseless)"
                          and r["train_seed"] == seed and r["scenario"] == kept[0]["scenario"]]
                    self.assertTrue(all((p == pc[0]).all() for p in pc), (stem, seed))
        self.assertGreater(seen, 300)
        # Experiment 7's confusion matrices (10 dB) recounted from the kept class ids.
        info, series, values = read_kept(os.path.join(out, "exp7_kinematic_predictions.npz"))
        with np.load(os.path.join(out, "exp7_truth.npz")) as z:
            truth, names = z["frames_kinematic"]["class_id"], [str(n) for n in z["classes_kinematic"]["name"]]
        counts = {}
        for r, v in zip(series_rows(series), values):
            if r["snr_db"] == "10":
                for t, p in zip(truth, v):
                    k = (r["method"], r["train_seed"], names[t], names[p])
                    counts[k] = counts.get(k, 0) + 1
        for r in rows(os.path.join(out, "exp7_confusion.csv")):
            self.assertEqual(int(r["count"]), counts.get((r["method"], r["train_seed"], r["true_class"],
                                                          r["predicted_class"]), 0), r)
        # predictions.py check agrees with all of it, and fails when one prediction changes.
        r = subprocess.run(["/usr/bin/python3", KEPT, "check", out], capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertIn("%d CSV rows recomputed from the kept predictions, 0 differ" % seen, r.stdout)
        changed = os.path.join(out, "changed")
        os.makedirs(changed)
        for f in ("exp7_kinematic.csv", "exp7_truth.npz"):
            shutil.copy(os.path.join(out, f), changed)
        ids = values.copy()
        f = int(np.flatnonzero(ids[0] == truth)[0])  # a frame series 0 decides right
        ids[0, f] = (truth[f] + 1) % len(names)
        with np.load(os.path.join(out, "exp7_kinematic_predictions.npz")) as z:
            arrays = {k: z[k] for k in z.files}
        b = int(info["bits"])
        bits = ((ids[:, :, None] + 1) >> np.arange(b - 1, -1, -1)) & 1
        arrays["values"] = np.packbits(bits.reshape(len(ids), -1).astype(np.uint8), axis=1)
        np.savez(os.path.join(changed, "exp7_kinematic_predictions.npz"), **arrays)
        r = subprocess.run(["/usr/bin/python3", KEPT, "check", changed, "7"], capture_output=True, text=True,
                           timeout=120)
        self.assertEqual(r.returncode, 1, r.stdout)
        s0 = series[0]
        self.assertIn("%r, accuracy: the CSV has" % ((str(s0["scenario"]), str(s0["method"]), str(s0["mask"]),
                                                      int(s0["n_pilots"]), float(s0["snr_db"]),
                                                      str(int(s0["train_seed"]))),), r.stderr)

    def check_claims(self, out):
        """claims.py on the test-size run: every claim tested, each family named with its size and
        correction; the paired difference of a row is the CSVs' mean difference; a results folder
        without one kept file gets the file and the command that writes it named."""
        r = subprocess.run(["/usr/bin/python3", CLAIMS, out, "--bootstrap", "200"], capture_output=True, text=True,
                           timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "claims.md")) as f:
            page = f.read()
        self.assertNotIn("not tested", page)
        self.assertIn("Experiment 7's families: [claims_kinematic.md](claims_kinematic.md).", page)
        with open(os.path.join(out, "claims_kinematic.md")) as f:
            page += f.read()  # experiment 7's families' tests
        for family, tests in (("SemS against MSE-DL", 6), ("SemS against the best feature SVM", 12),
                              ("SemS against Perfect CSI", 6),
                              ("experiment 7: the learned mask against the best hand pattern, every N_p and SNR", 6),
                              ("multipath delay: SemS against the best classical estimator", 2),
                              ("experiment 5: SemS at a pilot budget against the budget below it", 2)):
            self.assertIn("\n### %s\n" % family, page)
            self.assertIn('family "%s": %d tests, Holm\'s step-down correction over all of them at α = 0.05'
                          % (family, tests), page)
        e1 = rows(os.path.join(out, "exp1_recognition.csv"))
        mean = lambda m: sum(float(x["accuracy"]) for x in e1 if x["method"] == m and x["scenario"] == "default"  # noqa
                             and x["snr_db"] == "10") / 2
        line = [l for l in page.splitlines() if l.startswith("| experiment 1, default: SemS | 10 |")
                and "| MSE-DL |" in l][0]
        self.assertIn("| %+.3f ± " % (mean("SemS") - mean("MSE-DL")), line)
        bare = os.path.join(out, "without_exp4")
        os.makedirs(bare)
        for f in os.listdir(out):
            if f.endswith((".csv", ".npz")) and f != "exp4_delay_predictions.npz":
                shutil.copy(os.path.join(out, f), bare)
        r = subprocess.run(["/usr/bin/python3", CLAIMS, bare, "--bootstrap", "100"], capture_output=True, text=True,
                           timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("%s is missing: `bash scripts/evaluation/eval_full.sh` writes it"
                      % os.path.join(bare, "exp4_delay_predictions.npz"), r.stderr)
        with open(os.path.join(bare, "claims.md")) as f:
            self.assertIn("not tested: `exp4_delay_predictions.npz` missing", f.read())

    def check_experiment_7(self, out):
        """Experiment 7: every recognition method on the kinematic library, the staggered
        pattern beside the hand patterns, confusion matrices that account for every test frame,
        the pilot budget sweep; plot_kinematic.py draws and tabulates them."""
        e7 = rows(os.path.join(out, "exp7_kinematic.csv"))
        hand = ["SemS decoder (%s pilots)" % p for p in ("doppler", "uniform", "random", "staggered")]
        ms = ["SemS", "SemS + template bank", "MSE-DL", "Perfect CSI (noiseless)", "Perfect CSI (test SNR)",
              "SVM (uniform pilots)", "SVM (doppler pilots)"] + hand
        self.assertEqual({r["method"] for r in e7}, set(ms))
        self.assert_per_seed(e7, ms, TRAIN_SEEDS)
        self.assertEqual({r["scenario"] for r in e7}, {"kinematic"})
        self.assertTrue(all(float(r["us_per_frame"]) > 0 for r in e7), "every method is timed")
        conf = rows(os.path.join(out, "exp7_confusion.csv"))
        self.assertEqual({r["snr_db"] for r in conf}, {"10"})
        self.assertEqual(sorted({r["true_class"] for r in conf}), KINEMATIC)
        per_run, per_class = {}, {}
        for r in conf:
            k = (r["method"], r["train_seed"])
            per_run[k] = per_run.get(k, 0) + int(r["count"])
            per_class.setdefault(k, {})
            per_class[k][r["true_class"]] = per_class[k].get(r["true_class"], 0) + int(r["count"])
        self.assertEqual(set(per_run.values()), {24}, per_run)  # every test frame once
        self.assertEqual(len({tuple(sorted(v.items())) for v in per_class.values()}), 1)  # the same frames
        acc10 = {(r["method"], r["train_seed"]): float(r["accuracy"]) for r in e7 if r["snr_db"] == "10"}
        for (m, seed), n in per_run.items():  # the diagonal is the accuracy at 10 dB
            diag = sum(int(r["count"]) for r in conf if r["method"] == m and r["train_seed"] == seed
                       and r["true_class"] == r["predicted_class"])
            self.assertAlmostEqual(diag / n, acc10[(m, seed)], places=5)
        budget = rows(os.path.join(out, "exp7_pilot_budget.csv"))
        self.assertEqual({r["n_pilots"] for r in budget}, {"8"})
        self.assert_per_seed(budget, ["SemS", "SemS decoder (doppler pilots)", "SemS decoder (staggered pilots)"],
                             TRAIN_SEEDS)
        power = rows(os.path.join(out, "exp7_pilot_power.csv"))
        self.assertEqual({(r["method"], r["n_pilots"]) for r in power}, {("SemS (learned energies)", "32")})
        self.assert_per_seed(power, ["SemS (learned energies)"], TRAIN_SEEDS)
        self.assertEqual({(r["seed"], r["n_frames"]) for r in power}, {(e7[0]["seed"], "24")})  # the same frames
        bank = rows(os.path.join(out, "exp7_bank.csv"))
        bank_methods = ["SemS + template bank", "SemS decoder + template bank (doppler pilots)"]
        self.assertEqual({r["n_pilots"] for r in bank}, {"8"})
        self.assert_per_seed(bank, bank_methods, TRAIN_SEEDS)
        self.assertEqual({(r["seed"], r["n_frames"]) for r in bank}, {(e7[0]["seed"], "24")})  # the same frames
        with open(os.path.join(out, "bundles", "cls_kinematic_np8_doppler_templates_s%d" % SEED, "bundle.json")) as f:
            b = json.load(f)
        self.assertEqual(b["training"]["mask_pattern"], "doppler")
        self.assertEqual(b["decoder"]["settings"]["template_frames"], 48)  # every training frame of 60
        burst = rows(os.path.join(out, "exp7_burst.csv"))
        self.assertEqual({(r["method"], r["mask"], r["n_pilots"]) for r in burst},
                         {("SemS decoder (burst pilots)", "burst", "8")})
        self.assert_per_seed(burst, ["SemS decoder (burst pilots)"], TRAIN_SEEDS)
        self.assertEqual({(r["seed"], r["n_frames"]) for r in burst}, {(e7[0]["seed"], "24")})  # the same frames
        with open(os.path.join(out, "bundles", "cls_kinematic_np8_burst_s%d" % SEED, "mask.json")) as f:
            self.assertEqual(sorted(p[0] for p in json.load(f)["pilots"]), list(range(12, 20)))  # symbols 12..19
        learned = 0
        for name in os.listdir(os.path.join(out, "bundles")):  # masks of learned energies (mean 1)
            if name.startswith("cls_kinematic_sems_power"):
                learned += 1
                with open(os.path.join(out, "bundles", name, "mask.json")) as f:
                    mask = json.load(f)
                self.assertEqual(mask["origin"]["pilot_power"]["kind"], "learned")
                energies = mask.get("power", [1.0])  # absent: they stayed equal (tiny training)
                self.assertAlmostEqual(sum(energies) / len(energies), 1.0, places=5)
        self.assertEqual(learned, 2)  # one per training seed
        png = os.path.join(out, "png7")
        tables = os.path.join(out, "kinematic_tables.md")
        r = subprocess.run(["/usr/bin/python3", PLOT7, out, "--out", png, "--tables", tables],
                           capture_output=True, text=True, timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        for name in ("exp7_kinematic", "exp7_confusion", "exp7_pilot_budget"):
            p = os.path.join(png, name + ".png")
            self.assertTrue(os.path.exists(p) and os.path.getsize(p) > 1000, name)
        with open(tables) as f:
            md = f.read()
        self.assertIn("#### N_p = 8", md)
        self.assertIn("#### N_p = 32", md)
        self.assertIn("| SemS decoder (staggered pilots) |", md)
        self.assertIn("| SemS decoder (burst pilots), N_p 8 |", md)
        self.assertIn("learned pilot energies against equal energies", md)
        self.assertIn("with template banks, the learned mask against the Doppler pattern", md)
        # Paired on the kept predictions, each table naming its family: the learned mask against
        # the best hand pattern at N_p 8 and 32 x 3 SNRs; the energies at 32; the banks at 8.
        for family, tests in (("experiment 7: the learned mask against the best hand pattern, every N_p and SNR", 6),
                              ("experiment 7: learned pilot energies against equal energies, every N_p and SNR", 3),
                              ("experiment 7: with template banks, the learned mask against the Doppler pattern, "
                               "every N_p and SNR", 3)):
            self.assertIn('family "%s": %d tests, Holm' % (family, tests), md)
        self.assertNotIn("not available", md)
        # Without the kept predictions (a run of an older sems_eval): each paired table becomes a
        # note naming the missing file, the by-budget parts show accuracies only, and no verdict
        # or family is printed.
        bare = os.path.join(out, "without_predictions")
        os.makedirs(bare, exist_ok=True)
        for name in os.listdir(out):
            if name.endswith(".csv"):
                shutil.copy(os.path.join(out, name), bare)
        r = subprocess.run(["/usr/bin/python3", PLOT7, bare, "--out", os.path.join(bare, "png"), "--tables",
                            os.path.join(bare, "t.md")], capture_output=True, text=True, timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(bare, "t.md")) as f:
            md = f.read()
        self.assertIn("exp7_kinematic_predictions.npz is missing", md)
        self.assertIn("Accuracy only, not tested", md)
        self.assertIn("#### N_p = 8", md)
        for verdict in ("Holm", "ahead", "behind", "2 SE"):
            self.assertNotIn(verdict, md)

    def assert_per_seed(self, rs, methods, seeds, key=("method",)):
        """rs hold every one of methods (the first key field), and each key has, at every SNR
        point of its rows, exactly one row per training seed in seeds."""
        got = {}
        for r in rs:
            got.setdefault(tuple(r[k] for k in key) + (r["snr_db"],), []).append(r["train_seed"])
        missing = set(methods) - {k[0] for k in got}
        self.assertFalse(missing, "no rows for %s" % sorted(missing))
        for k, ts in got.items():
            self.assertEqual(sorted(ts), sorted(seeds), k)

    def test_002_bad_options_fail_clearly(self):
        with tempfile.TemporaryDirectory() as out:
            for args, word in ((["--size", "huge"], "--size"), (["--experiments", "10"], "--experiments"),
                              (["--exp8-frames", "0"], "--exp8-frames"), (["--exp8-np-sweep", "5000"], "--exp8-np-sweep"),
                              (["--exp8-parts", "all"], "--exp8-parts"), (["--first-seed", "-1"], "--first-seed"),
                              (["--exp8-super-frames", "1"], "--exp8-super-frames"),
                              (["--exp8-super-frame-start", "best"], "--exp8-super-frame-start"),
                              (["--exp7-parts", "all"], "--exp7-parts"), (["--exp7-np-sweep", "0"], "--exp7-np-sweep"),
                               (["--np-sweep", "0"], "--np-sweep"), (["--seeds", "0"], "--seeds"),
                               (["--test-frames", "1"], "--test-frames"), (["--test-frames", "9999999"], "--test-frames")):
                r = subprocess.run([EVAL, "--out", out] + args, capture_output=True, text=True, timeout=60)
                self.assertNotEqual(r.returncode, 0)
                self.assertIn(word, r.stderr)
            r = subprocess.run([EVAL], capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("out", r.stderr)
        r = subprocess.run(["/usr/bin/python3", PLOT, "/nonexistent/dir"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)

    def test_003_paired_tables_from_kept_predictions(self):
        """Experiment 7's paired tables from synthetic kept predictions with known answers: one
        seed, 400 frames; SemS right on 3 frames of 4, the Doppler pattern on 1 of 2 and the
        staggered one on 1 of 4 (the best, Doppler, is the rival): difference 0.25, SE
        sqrt(v/n) of the per-frame differences, ahead; learned energies identical to SemS:
        difference 0, SE 0, p = 1, tied; the bank part's file missing: its table names the file
        and the command that writes it."""
        sys.path.insert(0, FIGURES)
        import claims
        n = 400
        truth = [i % 2 for i in range(n)]
        sems = [t if i % 4 else 1 - t for i, t in enumerate(truth)]
        doppler = [t if i % 2 else 1 - t for i, t in enumerate(truth)]
        staggered = [t if i % 4 == 0 else 1 - t for i, t in enumerate(truth)]
        with tempfile.TemporaryDirectory() as d:
            write_truth(os.path.join(d, "exp7_truth.npz"), "7", "kinematic", 2127, truth, ["adult", "child", "car"])
            main = {("SemS", "learned (task)", 32, 10.0, 5, ): sems,
                    ("SemS decoder (doppler pilots)", "doppler", 32, 10.0, 5): doppler,
                    ("SemS decoder (staggered pilots)", "staggered", 32, 10.0, 5): staggered}
            write_kept(os.path.join(d, "exp7_kinematic_predictions.npz"), "7", "kinematic", 2127, main, 3)
            write_kept(os.path.join(d, "exp7_pilot_power_predictions.npz"), "7", "kinematic", 2127,
                       {("SemS (learned energies)", "learned (task, energies)", 32, 10.0, 5): sems}, 3)
            t = claims.exp7_tables(d, boots=4000, seed=3)
            self.assertEqual(list(t["hand"]), [32])
            row = t["hand"][32].splitlines()[-1]
            d_frames = np.array([(i % 4 != 0) - (i % 2 != 0) for i in range(n)], dtype=float)
            se = d_frames.std() / n ** 0.5  # the bootstrap SE of a mean over n frames, one seed
            cells = [c.strip() for c in row.strip("|").split("|")]
            self.assertEqual(cells[:3], ["10", "0.750", "0.500 (doppler)"], row)
            diff, got_se = (float(x) for x in cells[3].split(" ± "))
            self.assertEqual(diff, 0.25)
            self.assertAlmostEqual(got_se, se, delta=0.05 * se)
            self.assertEqual(cells[-1], "**ahead**", row)
            self.assertIn('family "%s": 1 test, Holm' % claims.EXP7_HAND, t["hand_text"])
            energies = t["energies"][32].splitlines()[-1]
            self.assertEqual([c.strip() for c in energies.strip("|").split("|")][3:],
                             ["+0.000 ± 0.000", "1", "1", "tied"], energies)
            self.assertIn("exp7_bank_predictions.npz is missing: `bash scripts/evaluation/eval_kinematic.sh` writes it",
                          t["bank"][None])
            self.assertIn("--exp7-parts bank", t["bank"][None])
            # A series on other test frames than the truth's is refused, naming both.
            write_kept(os.path.join(d, "exp7_bank_predictions.npz"), "7", "kinematic", 99,
                       {("SemS + template bank", "learned (task)", 8, 10.0, 5): sems}, 3)
            with self.assertRaises(ValueError) as e:
                claims.exp7_tables(d, boots=100)
            self.assertIn("test seed 99", str(e.exception))
            self.assertIn("test seed 2127", str(e.exception))

    def test_004_cache_reuses_only_networks_trained_with_the_same_settings(self):
        """A re-run reuses every cached network whose settings match, and retrains one whose
        stored key differs in a decoder setting (the classifier's tone fit) or in the scene,
        which the training record alone does not hold."""
        def run(out):
            r = subprocess.run([EVAL, "--size", "test", "--seeds", "1", "--experiments", "1", "--out", out,
                                "--threads", "1"], capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr + r.stdout[-2000:])
            text = r.stdout + r.stderr
            return ({l.split("model ")[1].split(":")[0] for l in text.splitlines() if ": training (" in l},
                    {l.split("model ")[1].split(":")[0] for l in text.splitlines() if ": reusing " in l})

        with tempfile.TemporaryDirectory() as out:
            trained, reused = run(out)
            self.assertGreater(len(trained), 5)
            self.assertEqual(reused, set())
            self.assertEqual(run(out), (set(), trained))
            # The key holds what bundle.json keeps outside its training record.
            d = os.path.join(out, "bundles", "cls_default_sems_s2026")
            with open(os.path.join(d, "eval_key.json")) as f:
                key = json.load(f)["key"]
            with open(os.path.join(d, "bundle.json")) as f:
                info = json.load(f)
            self.assertEqual(key["task"], "classify")
            self.assertEqual(key["frame"], info["frame"])
            self.assertEqual(key["scene"], info["training"]["scene"])
            self.assertEqual(set(key["classifier"]), set(info["decoder"]["settings"]))
            self.assertEqual(key["classifier"]["chirp_bins"], info["decoder"]["settings"]["chirp_bins"])
            for name, edit in (("cls_default_sems_s2026", lambda k: k["classifier"].update(chirp_bins=0)),
                               ("cls_any_doppler_s2026", lambda k: k.update(scene="another scene"))):
                path = os.path.join(out, "bundles", name, "eval_key.json")
                with open(path) as f:
                    stored = json.load(f)
                edit(stored["key"])
                with open(path, "w") as f:
                    json.dump(stored, f)
            self.assertEqual(run(out), ({"cls_default_sems_s2026", "cls_any_doppler_s2026"},
                                        trained - {"cls_default_sems_s2026", "cls_any_doppler_s2026"}))


    def test_005_bundles_and_masks_of_another_frame_are_refused_naming_the_field(self):
        """A shipped bundle of another frame than the run's is refused before anything runs, and a
        cached one reused with --reuse-bundles too, each naming the field and both values; so is
        sems_train's --mask of another grid, or with a pilot on one of the frame's guards."""
        models = os.path.join(SOURCE, "models")
        train = os.path.join(BUILD, "apps", "sems_train")
        mask = os.path.join(models, "delay_single", "mask.json")
        with tempfile.TemporaryDirectory() as out:
            for frame, texts in ((["--symbols", "16"], ["n_symbols: the mask has 32, the frame has 16"]),
                                 (["--symbols", "16", "--subcarriers", "128"],
                                  ["n_symbols: the mask has 32, the frame has 16",
                                   "n_subcarriers: the mask has 64, the frame has 128"]),
                                 (["--guards", "1"], ["is on guard subcarrier 1 of the frame"])):
                r = subprocess.run([train, "--task", "delay", "--mask", mask, "--frames", "20", "--epochs", "1",
                                    "--threads", "1", "--out", os.path.join(out, "b")] + frame,
                                   capture_output=True, text=True, timeout=120)
                self.assertNotEqual(r.returncode, 0, r.stdout[-2000:])
                for t in [mask] + texts:
                    self.assertIn(t, r.stderr, frame)
        base = [EVAL, "--size", "test", "--seeds", "1", "--experiments", "1", "--threads", "1"]
        with tempfile.TemporaryDirectory() as out:
            for flag, bundle, frame, field, values in (
                    ("--shipped-classifier", "classifier", ["--bandwidth-hz", "20e6"], "bandwidth_hz",
                     ("the bundle's frame has 30000000", "has 20000000")),
                    ("--shipped-delay-single", "delay_single", ["--symbols", "16"], "n_symbols",
                     ("the bundle's frame has 32", "has 16"))):
                r = subprocess.run(base + ["--out", out, "--only-shipped", flag, os.path.join(models, bundle)] + frame,
                                   capture_output=True, text=True, timeout=120)
                self.assertNotEqual(r.returncode, 0, r.stdout[-2000:])
                self.assertIn(flag, r.stderr)
                self.assertIn("frame field " + field + " differs", r.stderr)
                for v in values:
                    self.assertIn(v, r.stderr)
                self.assertNotIn("training (", r.stdout)  # refused before anything ran
            # A cache of the paper's frame, reused as is on a 20 MHz run.
            cached = os.path.join(out, "bundles", "cls_default_sems_s2026")
            shutil.copytree(os.path.join(models, "classifier"), cached)
            with open(os.path.join(cached, "eval_key.json"), "w") as f:
                json.dump({"key": {}, "train_seconds": 0}, f)
            r = subprocess.run(base + ["--out", out, "--reuse-bundles", "--bandwidth-hz", "20e6"],
                               capture_output=True, text=True, timeout=600)
            self.assertNotEqual(r.returncode, 0, r.stdout[-2000:])
            self.assertIn("model cls_default_sems_s2026 (--reuse-bundles", r.stderr)
            self.assertIn("frame field bandwidth_hz differs: the cached bundle's frame has 30000000, "
                          "the run's frame has 20000000", r.stderr)

    def test_006_experiment_8_tracks_paired_predictions(self):
        """Experiment 8 at its test size with two training seeds and both parts: every method's
        scores at every SNR and observation time, per training seed; each score recomputed from
        the saved per-track decisions and the truth (tracks shorter than an observation time
        left out); the noiseless CNN's decisions the same at every SNR; plot_tracks.py draws
        the figures and the paired tables."""
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "8", "--seeds", "2", "--out", out,
                                "--threads", "1"], capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr + r.stdout[-2000:])
            scores = rows(os.path.join(out, "exp8_tracks.csv"))
            truth = rows(os.path.join(out, "exp8_truth.csv"))
            preds = rows(os.path.join(out, "exp8_predictions.csv"))
            self.assertEqual(len(truth), 12)
            self.assertEqual({t["class"] for t in truth} - set(KINEMATIC), set())
            length = [int(t["frames"]) for t in truth]
            label = [int(t["class_id"]) for t in truth]
            self.assertTrue(all(1 <= n <= 8 for n in length), length)
            main = ["SemS-track", "SemS fusion", "MSE-DL fusion", "SVM over the track (doppler pilots)",
                    "Perfect-CSI spectrogram CNN (noiseless)"] + [
                "SemS decoder (%s pilots) %s" % (p, k) for p in ("doppler", "staggered") for k in ("+ track", "fusion")]
            budget = ["SemS-track", "SemS fusion"] + [
                "SemS decoder (%s pilots) %s" % (p, k) for p in ("doppler", "staggered", "burst")
                for k in ("+ track", "fusion")]
            got = {}
            for s in scores:
                got.setdefault((s["method"], s["n_pilots"], s["snr_db"], s["frames"]), []).append(s["train_seed"])
            for methods, np_ in ((main, "32"), (budget, "8")):
                for m in methods:
                    n = np_ if "CNN" not in m else "2048"
                    for snr in ("-10", "10", "30"):
                        for f in ("1", "2", "4", "8"):
                            if any(x >= int(f) for x in length):
                                self.assertEqual(sorted(got.get((m, n, snr, f), [])), sorted(TRAIN_SEEDS), (m, n, snr, f))
            self.assertFalse([k for k in got if k[0] not in main + budget], "unexpected methods")
            by_key = {(p["method"], p["n_pilots"], p["snr_db"], p["train_seed"], p["frames"]): p for p in preds}
            self.assertEqual(len(by_key), len(preds), "one decision row per method, budget, SNR, seed and time")
            for s in scores:
                p = by_key[(s["method"], s["n_pilots"], s["snr_db"], s["train_seed"], s["frames"])]
                d = [int(v) for v in p["predicted"].split()]
                self.assertEqual(len(d), 12)
                f = int(s["frames"])
                kept = [i for i in range(12) if length[i] >= f]
                self.assertEqual([d[i] for i in range(12) if length[i] < f], [-1] * (12 - len(kept)))
                self.assertEqual(int(s["n_tracks"]), len(kept))
                self.assertAlmostEqual(float(s["accuracy"]), sum(d[i] == label[i] for i in kept) / len(kept), places=5)
            for seed in TRAIN_SEEDS:
                cnn = {p["snr_db"]: p["predicted"] for k, p in by_key.items()
                       if k[0].startswith("Perfect-CSI") and k[3] == seed and k[4] == "8"}
                self.assertEqual(len(set(cnn.values())), 1, "the noiseless CNN's decisions do not depend on the SNR")
            r = subprocess.run(["/usr/bin/python3", os.path.join(SOURCE, "apps", "figures", "plot_tracks.py"), out,
                                "--bootstrap", "200"], capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("exp8_tracks.png", "exp8_pilot_budget.png", "track_tables.md"):
                self.assertGreater(os.path.getsize(os.path.join(out, name)), 1000, name)
            with open(os.path.join(out, "track_tables.md")) as f:
                text = f.read()
            for heading in ("## Accuracy at 10 dB, N_p = 32", "### against SemS fusion", "## Time to 90",
                            "## The adult/child pair", "## The quadcopter/hexacopter pair"):
                self.assertIn(heading, text)
            with open(os.path.join(out, "track_pilots.md")) as f:
                self.assertIn("## Pilot budget", f.read())

    def test_008_experiment_8_scores_a_shipped_track_bundle(self):
        """--shipped-track scores a shipped track bundle (its decision and its frame decoder's
        fusion, no training: train seed none) on the experiment's test tracks; a missing bundle
        is refused naming the option."""
        bundle = os.path.join(SOURCE, "models", "classifier_kinematic_track")
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "8", "--exp8-parts", "main", "--only-shipped",
                                "--shipped-track", bundle, "--out", out, "--threads", "1"],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr + r.stdout[-2000:])
            scores = rows(os.path.join(out, "exp8_tracks.csv"))
            self.assertEqual({s["method"] for s in scores}, {"shipped track bundle", "shipped track bundle's fusion"})
            self.assertEqual({s["train_seed"] for s in scores}, {"none"})
            self.assertEqual({s["model"] for s in scores}, {bundle})
            self.assertFalse(os.path.exists(os.path.join(out, "bundles")), "nothing is trained")
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "8", "--shipped-track", "/nonexistent/bundle",
                                "--out", out], capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("shipped-track", r.stderr)

    def test_009_experiment_8_super_frames(self):
        """The superframe part at the test size beside the budget part: the learned super-frame
        under the temporal decoder and its fusion, and the SemS decoder on its mask moved across
        the band frame by frame, at every SNR and time; their bundles hold F = 4 sets of N_p
        pilots (the moved one: set f is the SemS mask shifted by f·M/4 subcarriers); each score is
        its saved decisions'; plot_tracks.py writes the section of pilots across frames."""
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "8", "--seeds", "1", "--out", out,
                                "--exp8-parts", "budget,superframe", "--threads", "1"],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr + r.stdout[-2000:])
            scores = rows(os.path.join(out, "exp8_tracks.csv"))
            truth = rows(os.path.join(out, "exp8_truth.csv"))
            preds = {(p["method"], p["snr_db"], p["frames"]): p for p in rows(os.path.join(out, "exp8_predictions.csv"))}
            length = [int(t["frames"]) for t in truth]
            label = [int(t["class_id"]) for t in truth]
            new = ["SemS super-frame (F = 4) + track", "SemS super-frame (F = 4) fusion",
                   "SemS decoder (its mask on 4 subcarriers across frames) fusion"]
            for m in new:
                for snr in ("-10", "10", "30"):
                    for f in ("1", "2", "4", "8"):
                        if not any(x >= int(f) for x in length):
                            continue
                        got = [s for s in scores if (s["method"], s["snr_db"], s["frames"]) == (m, snr, f)]
                        self.assertEqual(len(got), 1, (m, snr, f))
                        self.assertEqual(got[0]["n_pilots"], "8")
                        d = [int(v) for v in preds[(m, snr, f)]["predicted"].split()]
                        kept = [i for i in range(len(truth)) if length[i] >= int(f)]
                        self.assertAlmostEqual(float(got[0]["accuracy"]),
                                               sum(d[i] == label[i] for i in kept) / len(kept), places=5)
            bundles = os.path.join(out, "bundles")
            sems = read_json(os.path.join(bundles, "cls_kinematic_np8_sems_s2026", "mask.json"))
            learned = read_json(os.path.join(bundles, "cls_kinematic_np8_sems_s2026_sf4_track", "mask.json"))
            moved = read_json(os.path.join(bundles, "cls_kinematic_np8_sems_s2026_shifted4", "mask.json"))
            self.assertEqual(len(learned["frames"]), 4)
            self.assertTrue(all(len(f["pilots"]) == 8 for f in learned["frames"]))
            m = sems["n_subcarriers"]
            for f, fr in enumerate(moved["frames"]):
                want = sorted([n, (k + f * m // 4) % m] for n, k in sems["pilots"])
                self.assertEqual(sorted(fr["pilots"]), want, f)
            r = subprocess.run(["/usr/bin/python3", os.path.join(SOURCE, "apps", "figures", "plot_tracks.py"), out,
                                "--bootstrap", "200"], capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "track_pilots.md")) as f:
                text = f.read()
            self.assertIn("## Pilots across frames: learned super-frames against the best repeated mask", text)
            self.assertIn("moved across the band", text)

    def test_007_holm_and_paired_bootstrap(self):
        """The paired statistics (paired_stats.py, which plot_tracks.py uses) against closed
        forms: Holm's step-down adjustment by hand; plot_tracks.py's bootstrap over tracks, SE
        sqrt(v/n); the two-level bootstrap: one seed gives sqrt(v/n), identical methods a
        difference of 0 with p = 1, and seed and frame effects the variance
        var(seed)/S + var(frame)/n + var(interaction)/(S n); pairing, verdicts and families."""
        sys.path.insert(0, FIGURES)
        import paired_stats as ps
        import plot_tracks
        self.assertIs(plot_tracks.holm, ps.holm)
        self.assertEqual(ps.holm([0.01, 0.04, 0.03, 0.5]), [0.04, 0.09, 0.09, 0.5])
        # 0.001 * 3; then 0.2 * 2 = 0.4; then 0.3 * 1, raised to 0.4 (step-down monotone); capped at 1.
        self.assertEqual([round(p, 12) for p in ps.holm([0.2, 0.3, 0.001])], [0.4, 0.4, 0.003])
        self.assertEqual(ps.holm([0.6, 0.7]), [1.0, 1.0])
        n = 400
        truth = [{"class_id": str(i % 2), "frames": "4"} for i in range(n)]
        a = " ".join(str(i % 2) if i % 4 else str(1 - i % 2) for i in range(n))  # 3/4 right
        b = " ".join(str(i % 2) if i % 2 else str(1 - i % 2) for i in range(n))  # 1/2 right
        p = plot_tracks.predictions([{"method": m, "n_pilots": "32", "snr_db": "10", "frames": "4",
                                      "train_seed": "1", "predicted": d} for m, d in (("A", a), ("B", b))], truth)
        res = p.paired("A", "B", 32, 32, 10.0, 4, np.random.default_rng(1), 4000)
        d = np.array([(i % 4 != 0) - (i % 2 != 0) for i in range(n)], dtype=float)
        self.assertAlmostEqual(res["diff"], 0.25, places=9)
        self.assertAlmostEqual(res["se"], d.std() / n ** 0.5, delta=0.1 * d.std() / n ** 0.5)
        self.assertLess(res["p"], 0.01)
        # Two levels, one seed: the frames' SE, sqrt(v/n) (v the population variance).
        ca = (np.arange(n) % 4 != 0).astype(float)  # per-frame correctness, a - b = d
        cb = (np.arange(n) % 2 != 0).astype(float)
        r = ps.two_level(ca[None], cb[None], np.random.default_rng(2), 4000)
        self.assertEqual(r["diff"], 0.25)
        self.assertAlmostEqual(r["se"], d.std() / n ** 0.5, delta=0.05 * d.std() / n ** 0.5)
        self.assertAlmostEqual(r["p"], math.erfc(0.25 / r["se"] / 2 ** 0.5), places=12)
        # Identical methods: no difference, no spread, p = 1, tied.
        same = ps.two_level(np.tile(ca, (3, 1)), np.tile(ca, (3, 1)), np.random.default_rng(3), 500)
        self.assertEqual((same["diff"], same["se"], same["p"]), (0.0, 0.0, 1.0))
        self.assertEqual(ps.verdict(same["diff"], ps.holm([same["p"]])[0]), "tied")
        # Seed and frame effects: the exact bootstrap variance of the mean difference.
        rng = np.random.default_rng(4)
        S, n = 4, 600
        dd = rng.normal(0, 1, (S, n)) * 0.3 + rng.normal(0, 1, (S, 1)) * 0.05 + rng.normal(0, 1, (1, n)) * 0.5
        mu = dd.mean()
        alpha, beta = dd.mean(axis=1) - mu, dd.mean(axis=0) - mu
        gamma = dd - mu - alpha[:, None] - beta[None, :]
        exact = (alpha.var() / S + beta.var() / n + gamma.var() / (S * n)) ** 0.5
        r = ps.two_level(dd, np.zeros((S, n)), np.random.default_rng(5), 4000)
        self.assertAlmostEqual(r["diff"], mu, places=12)
        self.assertAlmostEqual(r["se"], exact, delta=0.06 * exact)
        # The same scores in small units (rad² of rounding-sized differences): the same test, not a
        # spread taken for rounding.
        tiny = ps.two_level(dd * 1e-13, np.zeros((S, n)), np.random.default_rng(5), 4000)
        self.assertAlmostEqual(tiny["se"] / 1e-13, r["se"], delta=1e-9 * r["se"])
        self.assertAlmostEqual(tiny["p"], r["p"], places=9)
        # The seed level is in the SE: with these seeds' spread, a bootstrap over frames alone
        # of the seed-averaged differences misses most of it.
        frames_only = dd.mean(axis=0).std() / n ** 0.5
        self.assertGreater(exact, 1.3 * frames_only)
        # Seeds not shared: each method's resampled on its own (variance adds).
        r = ps.two_level(dd[:2], -dd[2:], np.random.default_rng(6), 2000, paired_seeds=False)
        self.assertAlmostEqual(r["diff"], dd[:2].mean() + dd[2:].mean(), places=12)
        self.assertEqual(r["seeds"], (2, 2))
        # Pairing: shared seeds row by row; a method without training pairs with every seed.
        x, y, z = np.zeros(3), np.ones(3), np.full(3, 2.0)
        a_, b_, paired = ps.align({"1": x, "2": y}, {None: z})
        self.assertTrue(paired)
        self.assertEqual((a_.tolist(), b_.tolist()), ([x.tolist(), y.tolist()], [z.tolist(), z.tolist()]))
        a_, b_, paired = ps.align({"1": x, "2": y, "3": z}, {"2": z, "3": x})
        self.assertEqual((a_.tolist(), b_.tolist(), paired), ([y.tolist(), z.tolist()], [z.tolist(), x.tolist()], True))
        self.assertIsNone(ps.align({}, {"1": x}))
        # Verdicts from the adjusted p, for accuracies and for errors (lower is better).
        self.assertEqual([ps.verdict(0.1, 0.01), ps.verdict(-0.1, 0.01), ps.verdict(0.1, 0.05)],
                         ["ahead", "behind", "tied"])
        self.assertEqual([ps.verdict(-0.1, 0.01, lower_is_better=True), ps.verdict(0.1, 0.01, lower_is_better=True)],
                         ["ahead", "behind"])
        self.assertAlmostEqual(ps.normal_p(1.959963984540054, 1.0), 0.05, places=12)
        # A family: Holm over its tests, each verdict from its adjusted p, the family named.
        fam = ps.Family("test family")
        for k, (diff, pv) in enumerate(((0.1, 0.01), (0.2, 0.04), (-0.3, 0.001))):
            fam.add(k, {"diff": diff, "se": 1.0, "p": pv})
        self.assertEqual([(k, round(adj, 12), v) for k, _, adj, v in fam.results()],
                         [(0, 0.02, "ahead"), (1, 0.04, "ahead"), (2, 0.003, "behind")])
        self.assertEqual(fam.describe(), 'family "test family": 3 tests, Holm\'s step-down correction over all of '
                                         'them at α = 0.05')

    def test_010_scripts_pass_the_test_frames(self):
        """eval_kinematic.sh --test-frames 30: every part's CSVs and kept predictions on 30 test
        frames per point, merged into the results with the truth, the scores checked, the paired
        tables and the claims page written; a malformed count and a script without the option
        are refused naming it."""
        env = dict(os.environ, SEMS_EVAL=EVAL)
        script = os.path.join(SOURCE, "scripts", "evaluation", "eval_kinematic.sh")
        with tempfile.TemporaryDirectory() as d:
            out, res = os.path.join(d, "out"), os.path.join(d, "results")
            r = subprocess.run(["bash", script, "--size", "test", "--test-frames", "30", "--out", out,
                                "--results", res], capture_output=True, text=True, timeout=900, env=env)
            self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr)
            for stem in KEPT_STEMS["7"]:
                self.assertEqual({x["n_frames"] for x in rows(os.path.join(res, stem + ".csv"))}, {"30"}, stem)
                info, series, values = read_kept(os.path.join(res, stem + "_predictions.npz"))
                self.assertEqual((int(info["n_frames"]), values.shape[1]), (30, 30), stem)
            self.assertIn("0 differ", r.stdout)
            with open(os.path.join(res, "claims_kinematic.md")) as f:
                self.assertIn("### %s" % "experiment 7: the learned mask against the best hand pattern, every N_p "
                              "and SNR", f.read())
            with open(os.path.join(res, "kinematic_tables.md")) as f:
                self.assertIn("Paired on the same 30 test frames", f.read())
            for args, word in ((["--test-frames", "many"], "--test-frames"),):
                r = subprocess.run(["bash", script, "--out", out, "--results", res] + args, capture_output=True,
                                   text=True, timeout=60, env=env)
                self.assertNotEqual(r.returncode, 0)
                self.assertIn(word, r.stderr)
            r = subprocess.run(["bash", os.path.join(SOURCE, "scripts", "evaluation", "eval_tracks.sh"), "--out", out,
                                "--results", res, "--test-frames", "30"], capture_output=True, text=True, timeout=60,
                               env=env)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("unknown option --test-frames", r.stderr)

    def test_012_experiment_9_angle(self):
        """Experiment 9's angle part: every method at every SNR for one and two targets, each
        one-target row's bound the ULA's closed form at the mean over its frames (positive,
        falling 10 dB per 10 dB of SNR in variance), beamforming near it at 30 dB, and the plot
        and table written."""
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "angle", "--out", out],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            with open(os.path.join(out, "exp9_angle.csv")) as f:
                rows = list(csv.DictReader(f))
            one = [x for x in rows if x["part"] == "one_target"]
            two = [x for x in rows if x["part"] == "two_targets"]
            snrs = sorted({float(x["snr_db"]) for x in rows})
            self.assertEqual(len(one), 3 * len(snrs))
            self.assertEqual(len(two), 3 * len(snrs))
            crb = {float(x["snr_db"]): float(x["crb_rad"]) for x in one if x["method"] == "beamforming"}
            for lo, hi in zip(snrs, snrs[1:]):
                self.assertAlmostEqual(crb[lo] ** 2 / crb[hi] ** 2, 10 ** ((hi - lo) / 10), delta=3e-5 * 10 ** ((hi - lo) / 10))  # 6 significant digits each
            bf30 = [x for x in one if x["method"] == "beamforming" and float(x["snr_db"]) == 30.0][0]
            self.assertLess(float(bf30["rmse_over_crb"]), 1.5)
            for x in two:
                self.assertTrue(0.0 <= float(x["both_found"]) <= 1.0, x)
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_angle.py"), out],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.getsize(os.path.join(out, "exp9_angle.png")) > 1000)
            with open(os.path.join(out, "exp9_angle.md")) as f:
                self.assertEqual(len([l for l in f if l.startswith("| ")]), 2 * (1 + len(snrs)))
        # With the shipped position bundle: its learned rows on its mask and array, beside the same
        # references on the same frames, and the paired table from the packed predictions.
        with tempfile.TemporaryDirectory() as out:
            bundle = os.path.join(SOURCE, "models", "position_ula8")
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "angle",
                                "--exp9-position-bundle", bundle, "--out", out], capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            self.assertIn("the mask and array of", r.stdout)
            with open(os.path.join(out, "exp9_angle.csv")) as f:
                one = [x for x in csv.DictReader(f) if x["part"] == "one_target"]
            self.assertEqual(len(one), 5 * len(snrs))
            at = {(x["method"], float(x["snr_db"])): float(x["rmse_rad"]) for x in one}
            crb30 = [float(x["crb_rad"]) for x in one if float(x["snr_db"]) == 30.0][0]
            for s in snrs:
                if s >= 0:  # the polish ends on beamforming's maximum: the same estimate to rounding
                    self.assertAlmostEqual(at[("SemS position (learned)", s)], at[("beamforming", s)], delta=1e-6)
            self.assertLess(at[("SemS position (learned)", 30.0)], 1.5 * crb30)
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_angle.py"), out],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.exists(os.path.join(out, "exp9_angle_predictions.npz")))
            with open(os.path.join(out, "exp9_angle.md")) as f:
                text = f.read()
            self.assertEqual(len([l for l in text.splitlines() if l.startswith("| ")]), 3 * (1 + len(snrs)))
            self.assertIn("Holm's step-down correction over all of them", text)
            self.assertIn("15 tests", text)  # 5 SNRs x 3 references
            single = {(x["method"], x["snr_db"]): float(x["rmse_rad"]) for x in one}
        # Two position bundles of one mask and array (the shipped one and a copy named as trained with
        # seed 99: the same weights), one per training seed: each one's rows carry its seed, the same
        # estimates as the shipped bundle alone; the table pools them and the tests resample seeds.
        with tempfile.TemporaryDirectory() as out:
            copy = os.path.join(out, "position_s99")
            shutil.copytree(bundle, copy)
            with open(os.path.join(copy, "bundle.json")) as f:
                b = json.load(f)
            b["position"]["training"]["seed"] = 99
            with open(os.path.join(copy, "bundle.json"), "w") as f:
                json.dump(b, f)
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "angle",
                                "--exp9-position-bundle", bundle + "," + copy, "--out", out],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            with open(os.path.join(out, "exp9_angle.csv")) as f:
                one = [x for x in csv.DictReader(f) if x["part"] == "one_target"]
            self.assertEqual(len(one), 7 * len(snrs))
            for x in one:
                if "[seed " in x["method"]:
                    self.assertEqual(float(x["rmse_rad"]), single[(x["method"].split(" [seed ")[0], x["snr_db"])])
            self.assertEqual({x["method"] for x in one if "[seed 99]" in x["method"]},
                             {"SemS position (learned) [seed 99]", "SemS angle network (no polish) [seed 99]"})
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_angle.py"), out],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "exp9_angle.md")) as f:
                text = f.read()
            self.assertIn("SemS position (learned), 2 seeds RMSE", text)
            self.assertIn("over 2 training seeds", text)
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "angle",
                                "--exp9-position-bundle", bundle + "," + bundle, "--out", out],
                               capture_output=True, text=True, timeout=120)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("the same seed (1)", r.stderr)

    def test_013_experiment_9_classes(self):
        """Experiment 9's classes part: the shipped kinematic classifier on the same frames seen by
        1, 4 and 8 elements; every CSV row recomputed from its kept predictions; at 30 dB the
        combination's beam finds the target (its answers are those at the true azimuth on nearly
        every frame); the figure and both families of paired tests written; bad input refused."""
        sys.path.insert(0, FIGURES)
        import predictions as kp
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "classes",
                                "--test-frames", "200", "--snrs", "-10,30", "--out", out],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            self.assertFalse(os.path.exists(os.path.join(out, "exp9_angle.csv")))
            with open(os.path.join(out, "exp9_classes.csv")) as f:
                rows = list(csv.DictReader(f))
            methods = {x["method"] for x in rows}
            self.assertEqual(methods, {"1 element", "4 elements, beamformed", "8 elements, beamformed",
                                       "4 elements, beamformed at the true azimuth",
                                       "8 elements, beamformed at the true azimuth",
                                       "one antenna at +10 log10 4 dB", "one antenna at +10 log10 8 dB"})
            self.assertEqual(len(rows), 7 * 2)
            self.assertEqual({x["train_seed"] for x in rows}, {"2026"})  # the shipped bundle's
            checked, problems, missing = kp.check(out, ["9"])
            self.assertEqual((checked, problems, missing), (14, [], []))
            exp = kp.Experiment(out, "9")
            pred = {k[1]: kept.values(i) for k, (kept, i) in exp.series.items() if k[4] == 30.0}
            same = np.mean(pred["8 elements, beamformed"] == pred["8 elements, beamformed at the true azimuth"])
            self.assertGreater(same, 0.95)
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_array_classes.py"), out,
                                "--bootstrap", "200"], capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.getsize(os.path.join(out, "exp9_classes.png")) > 1000)
            with open(os.path.join(out, "exp9_classes.md")) as f:
                text = f.read()
            self.assertIn("every SNR\": 6 tests", text)   # 4 and 8 against 1, 8 against 4
            self.assertIn("every SNR\": 8 tests", text)   # beamformed against the true azimuth and the gain
            self.assertIn("**The adult/child pair.**", text)
            self.assertEqual(len([l for l in text.splitlines() if l.startswith("| 8 elements, beamformed, per frame |")]), 1)
            bad = [(["--exp9-parts", "nope"], "\"nope\" is not one of angle, classes"),
                   (["--exp9-class-elements", "0,8"], "--exp9-class-elements"),
                   (["--exp9-classifier-bundles", "delay_single"], "not a classifier bundle"),
                   (["--exp9-classifier-bundles", "classifier_kinematic,classifier_kinematic"], "the same seed")]
            for args, words in bad:
                parts = [] if "--exp9-parts" in args else ["--exp9-parts", "classes"]
                r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--out", out] + parts + args,
                                   capture_output=True, text=True, timeout=120)
                self.assertNotEqual(r.returncode, 0, args)
                self.assertIn(words, r.stderr, args)
        # The experiment's one command, at the test size: both parts, their tables and figures.
        with tempfile.TemporaryDirectory() as work:
            res = os.path.join(work, "results")
            r = subprocess.run(["bash", os.path.join(SOURCE, "scripts", "evaluation", "eval_arrays.sh"), "--size", "test",
                                "--out", os.path.join(work, "out"), "--results", res],
                               capture_output=True, text=True, timeout=300, env=dict(os.environ, SEMS_EVAL=EVAL))
            self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])
            for name in ("exp9_angle.md", "exp9_angle.png", "exp9_angle_predictions.npz", "exp9_classes.md",
                         "exp9_classes.png", "exp9_classes_predictions.npz", "exp9_truth.npz", "exp9_tracks.csv",
                         "exp9_tracks_predictions.csv", "exp9_tracks_truth.csv", "exp9_mimo.md", "exp9_mimo.png",
                         "exp9_mimo_predictions.npz", "eval_arrays.log"):
                self.assertTrue(os.path.exists(os.path.join(res, name)), name)

    def test_014_experiment_9_tracks(self):
        """Experiment 9's tracks part: the shipped track bundle over the same straight tracks seen by
        1, 4 and 8 elements; every accuracy recomputed from the kept decisions and the tracks' truth,
        each observation time scored on the tracks that long; a bundle that is not a track bundle
        is refused."""
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "tracks",
                                "--exp9-track-count", "20", "--snrs", "0,30", "--out", out],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            with open(os.path.join(out, "exp9_tracks_truth.csv")) as f:
                truth = list(csv.DictReader(f))
            with open(os.path.join(out, "exp9_tracks.csv")) as f:
                rows = list(csv.DictReader(f))
            with open(os.path.join(out, "exp9_tracks_predictions.csv")) as f:
                kept = list(csv.DictReader(f))
            self.assertEqual(len(truth), 20)
            self.assertEqual({x["method"] for x in rows}, {"1 element", "4 elements, beamformed", "8 elements, beamformed"})
            self.assertEqual(sorted({int(x["frames"]) for x in rows}), [1, 2, 4, 8])
            self.assertEqual(len(kept), 3 * 2 * 4)
            length = np.array([int(t["frames"]) for t in truth])
            label = np.array([int(t["class_id"]) for t in truth])
            self.assertTrue(np.all(length >= 1) and np.all(length <= 8))
            for x in rows:
                k = [y for y in kept if (y["method"], y["snr_db"], y["frames"]) == (x["method"], x["snr_db"], x["frames"])]
                pred = np.array([int(v) for v in k[0]["predicted"].split()])
                scored = length >= int(x["frames"])
                self.assertEqual(int(x["tracks"]), int(scored.sum()))
                self.assertTrue(np.all(pred[~scored] == -1))
                self.assertAlmostEqual(float(x["accuracy"]), float(np.mean(pred[scored] == label[scored])), places=5)
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "tracks",
                                "--exp9-track-bundle", "classifier_kinematic", "--out", out],
                               capture_output=True, text=True, timeout=120)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("is not a track bundle", r.stderr)

    def test_015_a_pairs_track_bundles_with_an_array(self):
        """eval_adult_child.sh --size test: three acf_tcn track bundles of the adult/child pair,
        experiment 9's tracks part on each drawing the pair's tracks alone (the classes their track
        record was trained on, not the frame bundle's six), the table from the three runs; the
        table refuses runs of other test tracks and a missing file, naming them."""
        env = dict(os.environ, SEMS_EVAL=EVAL, SEMS_TRAIN=os.path.join(BUILD, "apps", "sems_train"))
        script = os.path.join(SOURCE, "scripts", "evaluation", "eval_adult_child.sh")
        with tempfile.TemporaryDirectory() as d:
            out, res = os.path.join(d, "out"), os.path.join(d, "results")
            r = subprocess.run(["bash", script, "--size", "test", "--out", out, "--results", res],
                               capture_output=True, text=True, timeout=600, env=env)
            self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr)
            for s in (2026, 2027, 2028):
                with open(os.path.join(out, "bundle_s%d" % s, "bundle.json")) as f:
                    self.assertEqual(json.load(f)["track"]["temporal"]["kind"], "acf_tcn")
                with open(os.path.join(res, "adult_child_track", "s%d" % s, "exp9_tracks_truth.csv")) as f:
                    self.assertEqual({x["class"] for x in csv.DictReader(f)}, {"adult", "child"})
            with open(os.path.join(res, "adult_child_track.md")) as f:
                page = f.read()
            self.assertIn("3 track bundles", page)
            self.assertIn('family "more elements against fewer, every SNR": 9 tests', page)
            runs = [os.path.join(res, "adult_child_track", "s%d" % s) for s in (2026, 2027)]
            with open(os.path.join(runs[1], "exp9_tracks_truth.csv")) as f:
                lines = f.read().splitlines()
            track, class_id, name, frames = lines[1].split(",")  # the first track of another class
            lines[1] = ",".join((track, str(int(class_id) + 1), name, frames))
            with open(os.path.join(runs[1], "exp9_tracks_truth.csv"), "w") as f:
                f.write("\n".join(lines) + "\n")
            tab = os.path.join(SOURCE, "apps", "figures", "pair_tracks.py")
            r = subprocess.run(["/usr/bin/python3", tab] + runs, capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("%s holds other test tracks than %s" % (runs[1], runs[0]), r.stderr)
            os.remove(os.path.join(runs[0], "exp9_tracks_predictions.csv"))
            r = subprocess.run(["/usr/bin/python3", tab] + runs, capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn(os.path.join(runs[0], "exp9_tracks_predictions.csv") + " is missing", r.stderr)

    def test_016_experiment_9_mimo(self):
        """Experiment 9's MIMO part: every mask at every SNR; each learned mask's bound at or
        above the virtual array's floor and within a few per cent of it, the same pilots' above
        time division's (the transmit beam's nulls, and no virtual aperture); the
        maximum-likelihood estimate near each mask's bound at 30 dB; the table and figure written
        from the packed predictions; the array refused by name when it has one transmit element."""
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "mimo,mimo_budget",
                                "--out", out], capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            with open(os.path.join(out, "exp9_mimo_budget.csv")) as f:
                budget = list(csv.DictReader(f))
            self.assertEqual(sorted({int(x["n_pilots"]) for x in budget}), [4, 8])
            for np_ in (4, 8):
                rows = [x for x in budget if int(x["n_pilots"]) == np_]
                low = [float(x["mean_crb_0db_rad2"]) for x in rows if x["form"] == "virtual array floor"][0]
                for x in rows:  # the floor of masks whose pilots each come from one element
                    if x["form"] not in ("virtual array floor", "same pilots"):
                        self.assertGreaterEqual(float(x["mean_crb_0db_rad2"]), (1 - 1e-7) * low, x)
            with open(os.path.join(out, "exp9_mimo_masks.csv")) as f:
                masks = list(csv.DictReader(f))
            floor = [float(x["mean_crb_0db_rad2"]) for x in masks if x["form"] == "virtual array floor"][0]
            kept = {x["form"]: float(x["mean_crb_0db_rad2"]) for x in masks if x["chosen"] == "1" and x["form"] != "learned"}
            learned = [float(x["mean_crb_0db_rad2"]) for x in masks if x["form"] == "learned"]
            self.assertEqual(sorted(kept), ["frequency division", "same pilots", "time division"])
            self.assertEqual(len(learned), 3)
            for v in learned + [kept["time division"], kept["frequency division"]]:
                self.assertGreaterEqual(v, (1 - 1e-7) * floor)  # the CSV's 8 significant digits
            for v in learned:
                self.assertLess(v, 1.2 * floor)
            self.assertGreater(kept["same pilots"], 2.0 * kept["time division"])
            for x in masks:  # each form's kept pattern is its lowest bound
                if x["form"] in kept:
                    self.assertLessEqual(kept[x["form"]], float(x["mean_crb_0db_rad2"]))
            with open(os.path.join(out, "exp9_mimo.csv")) as f:
                rows = list(csv.DictReader(f))
            snrs = sorted({float(x["snr_db"]) for x in rows})
            self.assertEqual(len(rows), 6 * len(snrs))
            for x in rows:
                if float(x["snr_db"]) == 30.0 and x["method"] != "same pilots":
                    # 40 frames measure an RMSE within about 11 %: 1.5 is over four standard errors.
                    self.assertLess(float(x["rmse_over_crb"]), 1.5, x)
            self.assertEqual(len(os.listdir(os.path.join(out, "masks_mimo"))), 6)
            os.makedirs(os.path.join(out, "results"))
            for name in ("exp9_mimo.csv", "exp9_mimo_masks.csv", "exp9_mimo_predictions.csv"):
                shutil.copy(os.path.join(out, name), os.path.join(out, "results", name))
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_mimo.py"), os.path.join(out, "results")],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("exp9_mimo.md", "exp9_mimo.png", "exp9_mimo_predictions.npz"):
                self.assertTrue(os.path.exists(os.path.join(out, "results", name)), name)
            r = subprocess.run([EVAL, "--size", "test", "--experiments", "9", "--exp9-parts", "mimo",
                                "--exp9-mimo-array", "ula8_3g", "--out", out], capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("--exp9-mimo-array: ula8_3g has 1 transmit element", r.stderr)

    def test_011_experiment_7_range_under_a_link_budget(self):
        """The range part: every frame in a range bin of its class, each bin's mean SNR inside
        the radar equation's values for the class's RCS interval and the bin's ranges (the
        module's own link_budget, through the bindings), the plot and table written; bad input
        refused by name."""
        from gnuradio import sems
        bundle = os.path.join(SOURCE, "models", "classifier_sdr_2g4")
        scene = os.path.join(SOURCE, "models", "scenes", "kinematic_sdr_budget.json")
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([EVAL, "--out", out, "--experiments", "7", "--exp7-parts", "range",
                                "--exp7-range-bundle", bundle, "--exp7-range-scene", scene,
                                "--exp7-range-frames", "600"], capture_output=True, text=True, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            with open(os.path.join(out, "exp7_range.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(sum(int(x["frames"]) for x in rows), 600)
            sc = sems.scene.load(scene)
            b = sc.budget()
            fs = sems.frame_file.find("sdr_2g4_20mhz").frame
            rcs = {c["name"]: c["rcs_dbsm"] for c in json.loads(sc.library().to_json())["classes"]}
            for x in rows:
                lo, hi = rcs[x["class"]]
                r0, r1 = float(x["range_min_m"]), float(x["range_max_m"])
                snr = float(x["mean_snr_db"])
                self.assertGreaterEqual(snr, b.snr_db(fs, r1, lo) - 1e-3, x)
                self.assertLessEqual(snr, b.snr_db(fs, r0, hi) + 1e-3, x)
                n, acc = int(x["frames"]), float(x["accuracy"])
                self.assertAlmostEqual(acc * n, round(acc * n), places=3)
            r = subprocess.run(["/usr/bin/python3", os.path.join(FIGURES, "plot_range.py"), out],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.getsize(os.path.join(out, "exp7_range.png")) > 1000)
            with open(os.path.join(out, "range_table.md")) as f:
                self.assertEqual(len([l for l in f if l.startswith("| ")]), 1 + len(set(x["class"] for x in rows)))
            for args, word in ((["--exp7-range-scene", scene], "--exp7-range-bundle"),
                               (["--exp7-range-bundle", bundle, "--exp7-range-scene",
                                 os.path.join(SOURCE, "models", "scenes", "kinematic_any.json")], "link_budget"),
                               (["--exp7-range-bundle", os.path.join(SOURCE, "models", "classifier"),
                                 "--exp7-range-scene", scene], "class library"),
                               (["--exp7-range-bundle", bundle, "--exp7-range-scene", scene,
                                 "--exp7-range-frames", "-5"], "--exp7-range-frames")):
                r = subprocess.run([EVAL, "--out", out, "--experiments", "7", "--exp7-parts", "range"] + args,
                                   capture_output=True, text=True, timeout=120)
                self.assertNotEqual(r.returncode, 0)
                self.assertIn(word, r.stderr)

    def test_013_model_card_refuses_the_training_seed(self):
        """A card on the seed its bundle was trained with would score the first training frames
        again: refused, naming the field and the option; another seed measures the card."""
        with tempfile.TemporaryDirectory() as d:
            bundle = os.path.join(d, "classifier_fast")
            shutil.copytree(os.path.join(SOURCE, "models", "classifier_fast"), bundle)
            self.assertEqual(read_json(os.path.join(bundle, "bundle.json"))["training"]["seed"], 1)
            os.remove(os.path.join(bundle, "model_card.json"))
            r = subprocess.run([EVAL, "--model-card", bundle], capture_output=True, text=True, timeout=120)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("training.seed", r.stderr)
            self.assertIn("give another --card-seed", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(bundle, "model_card.json")))
            r = subprocess.run([EVAL, "--model-card", bundle, "--card-seed", "2", "--card-frames", "64",
                                "--card-snrs", "10", "--card-speed-frames", "64"],
                               capture_output=True, text=True, timeout=300)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(read_json(os.path.join(bundle, "model_card.json"))["test"]["seed"], 2)


if __name__ == "__main__":
    gr_unittest.run(qa_sems_eval)
