#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""End-to-end: sems_eval --size test --seeds 2 writes the seven experiments' CSVs (every learned
method once per training seed, on the same test frames), and plot_results.py and
plot_kinematic.py draw one PNG per experiment and the tables from them; bad options fail
clearly."""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

from gnuradio import gr_unittest

BUILD = os.environ.get("SEMS_BUILD_DIR", "")
SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
EVAL = os.path.join(BUILD, "apps", "sems_eval")
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
KINEMATIC = ["adult", "bicyclist", "car", "child", "hexacopter", "quadcopter"]
SEED = 2026  # sems_eval's default --seed: the training seeds are SEED and SEED + 1
TRAIN_SEEDS = {str(SEED), str(SEED + 1)}


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


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
            for args, word in ((["--size", "huge"], "--size"), (["--experiments", "9"], "--experiments"),
                              (["--exp8-frames", "0"], "--exp8-frames"), (["--exp8-np-sweep", "5000"], "--exp8-np-sweep"),
                              (["--exp8-parts", "all"], "--exp8-parts"), (["--first-seed", "-1"], "--first-seed"),
                              (["--exp8-super-frames", "1"], "--exp8-super-frames"),
                              (["--exp8-super-frame-start", "best"], "--exp8-super-frame-start"),
                              (["--exp7-parts", "all"], "--exp7-parts"), (["--exp7-np-sweep", "0"], "--exp7-np-sweep"),
                               (["--np-sweep", "0"], "--np-sweep"), (["--seeds", "0"], "--seeds")):
                r = subprocess.run([EVAL, "--out", out] + args, capture_output=True, text=True, timeout=60)
                self.assertNotEqual(r.returncode, 0)
                self.assertIn(word, r.stderr)
            r = subprocess.run([EVAL], capture_output=True, text=True, timeout=60)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("out", r.stderr)
        r = subprocess.run(["/usr/bin/python3", PLOT, "/nonexistent/dir"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)

    def test_003_learned_vs_hand_errors_use_each_methods_own_frames(self):
        """The 2-SE comparison of the learned mask with the best hand pattern: each mean's error
        is floored by the binomial error on that method's own test frames (frames x seeds); a
        bound's rows beside them on 10x the frames (the Bayes classifier's 30 000) must not
        shrink it. Closed form here: two methods at p = 0.9 on 3 000 frames x 3 seeds with no
        seed spread: 2 SE = 2 sqrt(2 p (1-p) / 9000) = 0.0089."""
        sys.path.insert(0, os.path.dirname(PLOT))
        import plot_results

        def row(method, acc, seed, frames=3000):
            return {"scenario": "any", "method": method, "snr_db": "10", "accuracy": str(acc),
                    "n_frames": str(frames), "train_seed": str(seed)}

        rs = [row(m, a, s) for s in (1, 2, 3) for m, a in (("SemS", 0.895), ("SemS decoder (doppler pilots)", 0.9))]
        two_se = 2 * (2 * 0.9 * 0.1 / 9000) ** 0.5  # the floor dominates: no spread over seeds
        for extra in ([], [row("Bayes classifier (bound)", 0.95, "none", frames=30000)]):
            line = plot_results.learned_vs_hand(rs + extra, "any").splitlines()[-1]
            self.assertIn("-0.005 ± %.3f" % two_se, line, line)  # well within: 0.0089 > 0.005
            self.assertTrue(line.endswith("| no | yes |"), line)  # a tie: not ahead, not behind
        rs = [row(m, a, s) for s in (1, 2, 3) for m, a in (("SemS", 0.88), ("SemS decoder (doppler pilots)", 0.9))]
        line = plot_results.learned_vs_hand(rs, "any").splitlines()[-1]
        self.assertTrue(line.endswith("| no | **no** |"), line)  # 0.02 is beyond 2 SE
        rs = [row(m, a, s) for s in (1, 2, 3) for m, a in (("SemS", 0.92), ("SemS decoder (doppler pilots)", 0.9))]
        line = plot_results.learned_vs_hand(rs, "any").splitlines()[-1]
        self.assertTrue(line.endswith("| **yes** | yes |"), line)  # ahead: 0.02 > 2 SE

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
            sems = json.load(open(os.path.join(bundles, "cls_kinematic_np8_sems_s2026", "mask.json")))
            learned = json.load(open(os.path.join(bundles, "cls_kinematic_np8_sems_s2026_sf4_track", "mask.json")))
            moved = json.load(open(os.path.join(bundles, "cls_kinematic_np8_sems_s2026_shifted4", "mask.json")))
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
        """plot_tracks.py's statistics against closed forms: Holm's step-down adjustment, and the
        paired bootstrap's standard error of a mean difference of 0/1 correctness (sqrt(v/n))."""
        sys.path.insert(0, os.path.join(SOURCE, "apps", "figures"))
        import numpy as np
        import plot_tracks
        self.assertEqual(plot_tracks.holm([0.01, 0.04, 0.03, 0.5]), [0.04, 0.09, 0.09, 0.5])
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

if __name__ == "__main__":
    gr_unittest.run(qa_sems_eval)
