#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Read, merge and check the per-frame predictions that sems_eval keeps beside its CSVs.

    predictions.py show FILE                  what a kept file holds
    predictions.py merge OUT IN [IN ...]      one file from the parts of a split run
    predictions.py check RESULTS [1,3,...]    every CSV score recomputed from the kept files

For experiments 1, 3, 4, 5, 7 and 9 (its classes part), sems_eval writes beside each CSV <stem>.csv the file
<stem>_predictions.npz (every method's output on every test frame, at every SNR, pilot
budget and training seed: the predicted class id, or the delay-index error as float32) and
one exp<N>_truth.npz per experiment (each test frame's class id, true delay index, range and
radial velocity, and what identifies it: scenario, test seed, frame index). Both are NumPy
.npz archives that numpy.load reads without pickles; docs/reference/file_formats.md ("Kept
predictions") has the layout. `sems_eval --only-shipped` writes <stem>_predictions.npz, which
scripts/evaluation/eval_full.sh keeps as shipped_<stem>_predictions.npz (`predictions.py merge`),
read with their experiment, as plot_results.py reads shipped_<stem>.csv.

`check` recomputes each CSV row's accuracy and macro-F1 (or mean, RMS and median absolute error
and the fraction above half an index) from the kept files and compares it with the CSV as
written (6 significant digits); it exits 1 naming the first rows that differ.
"""
import csv
import io
import math
import os
import sys
import zipfile
from collections import OrderedDict

import numpy as np

FORMAT = "sems_eval kept predictions"
VERSION = 1

# Experiment -> its CSV stems, each with the sems_eval arguments of the part that writes it;
# the script that runs the documented experiment.
SOURCES = OrderedDict([
    ("1", [("exp1_recognition", "--experiments 1")]),
    ("3", [("exp3_conditions", "--experiments 3")]),
    ("4", [("exp4_delay", "--experiments 4")]),
    ("5", [("exp5_pilot_budget", "--experiments 5")]),
    ("7", [("exp7_kinematic", "--experiments 7 --exp7-parts main"),
           ("exp7_pilot_budget", "--experiments 7 --exp7-parts budget"),
           ("exp7_pilot_power", "--experiments 7 --exp7-parts power"),
           ("exp7_bank", "--experiments 7 --exp7-parts bank"),
           ("exp7_burst", "--experiments 7 --exp7-parts burst")]),
    ("9", [("exp9_classes", "--experiments 9 --exp9-parts classes")]),
])
SCRIPTS = {"1": "scripts/evaluation/eval_full.sh", "3": "scripts/evaluation/eval_full.sh",
           "4": "scripts/evaluation/eval_full.sh", "5": "scripts/evaluation/eval_full.sh",
           "7": "scripts/evaluation/eval_kinematic.sh", "9": "scripts/evaluation/eval_arrays.sh"}


class Missing(Exception):
    """A kept file an analysis needs is not there: the message names it and what writes it."""


def missing_message(results, name, experiment, args):
    return ("%s is missing: `bash %s` writes it (or a run of its own, `build/apps/sems_eval --size full %s "
            "--out DIR`, into DIR)" % (os.path.join(results, name), SCRIPTS[experiment], args))


def _record(z, name):
    a = z[name]
    return {k: a[k][0].item() for k in a.dtype.names}


def unpack_ids(raw, n_frames, bits):
    """Class ids (int16, -1 = no decision) from rows packed `bits` per frame, most significant bit
    first, each row padded to whole bytes (the kept format)."""
    raw = np.asarray(raw, dtype=np.uint8)
    u = np.unpackbits(raw, axis=-1)[..., :n_frames * bits].reshape(raw.shape[:-1] + (n_frames, bits))
    weights = (1 << np.arange(bits - 1, -1, -1)).astype(np.int16)
    return (u.astype(np.int16) * weights).sum(axis=-1).astype(np.int16) - 1


class Kept:
    """One <stem>_predictions.npz: `series` (structured array, one record per series), `info`, and
    values(i): the class ids (int16) or the delay-index errors (float32) of series i."""

    def __init__(self, path):
        self.path = path
        with np.load(path, allow_pickle=False) as z:
            self.info = _record(z, "info")
            if self.info.get("format") != FORMAT or self.info.get("version") != VERSION:
                raise ValueError("%s is not a kept-predictions file of version %d" % (path, VERSION))
            self.series = z["series"]
            self.raw = z["values"]
        self.experiment = self.info["experiment"]
        self.quantity = self.info["quantity"]
        self.bits = int(self.info["bits"])
        self.n_frames = int(self.info["n_frames"])

    def __len__(self):
        return len(self.series)

    def key(self, i):
        """(scenario, method, mask, n_pilots, snr_db, train_seed or None)."""
        s = self.series[i]
        seed = int(s["train_seed"])
        return (str(s["scenario"]), str(s["method"]), str(s["mask"]), int(s["n_pilots"]), float(s["snr_db"]),
                None if seed < 0 else str(seed))

    def values(self, i=None):
        """Series i's per-frame values (all series, one row each, when i is None)."""
        raw = self.raw if i is None else self.raw[i]
        if self.quantity == "class_id":
            return unpack_ids(raw, self.n_frames, self.bits)
        return raw


class Truth:
    """One exp<N>_truth.npz: per scenario its test seed and frames (structured: frame, class_id,
    delay_index, range_m, velocity_mps) and its class names by id."""

    def __init__(self, path):
        self.path = path
        with np.load(path, allow_pickle=False) as z:
            self.info = _record(z, "info")
            if self.info.get("format") != FORMAT or self.info.get("version") != VERSION:
                raise ValueError("%s is not a kept truth file of version %d" % (path, VERSION))
            sc = z["scenarios"]
            self.scenarios = OrderedDict((str(r["scenario"]), (int(r["test_seed"]), int(r["n_frames"]))) for r in sc)
            self.frames = {s: z["frames_" + s] for s in self.scenarios}
            self.classes = {s: [str(n) for n in z["classes_" + s]["name"]] for s in self.scenarios}


class Experiment:
    """Every kept file of one experiment in RESULTS (its parts and the shipped_ rows) with its
    truth. scores(...) gives each training seed's per-frame score of one method at one point:
    correctness (1.0 / 0.0) for class ids, the absolute delay-index error for delays.
    `missing` lists the messages of the parts whose files are absent; `require(stem)` raises
    Missing with that message."""

    def __init__(self, results, experiment):
        self.results, self.experiment = results, experiment
        self.missing = OrderedDict()
        truth = os.path.join(results, "exp%s_truth.npz" % experiment)
        self.truth = Truth(truth) if os.path.exists(truth) else None
        self.series = OrderedDict()  # (scenario, method, mask, n_pilots, snr, seed) -> (Kept, index)
        self.stems = []
        for stem, args in SOURCES[experiment]:
            path = os.path.join(results, stem + "_predictions.npz")
            if not os.path.exists(path):
                self.missing[stem] = missing_message(results, stem + "_predictions.npz", experiment, args)
                continue
            if self.truth is None:
                self.missing[stem] = missing_message(results, "exp%s_truth.npz" % experiment, experiment, args)
                continue
            self.stems.append(stem)
            for p in (path, os.path.join(results, "shipped_" + stem + "_predictions.npz")):
                if os.path.exists(p):
                    self._add(Kept(p))
        self.lower_is_better = experiment in ("4", "5")

    def _add(self, kept):
        if kept.experiment != self.experiment:
            raise ValueError("%s holds experiment %s, not %s" % (kept.path, kept.experiment, self.experiment))
        for i in range(len(kept)):
            k = kept.key(i)
            seed, n = self.truth.scenarios.get(k[0], (None, None))
            test_seed = int(kept.series[i]["test_seed"])
            if seed is None or seed != test_seed or n != kept.n_frames:
                raise ValueError("%s: %s at %g dB was scored on other test frames (scenario %s, test seed %d, %d "
                                 "frames) than %s has (%s)" % (
                                     kept.path, k[1], k[4], k[0], test_seed, kept.n_frames, self.truth.path,
                                     "none" if seed is None else "test seed %d, %d frames" % (seed, n)))
            if k in self.series:
                other, j = self.series[k]
                if not np.array_equal(other.raw[j], kept.raw[i]):
                    raise ValueError("%s and %s disagree on %s" % (other.path, kept.path, k))
                continue
            self.series[k] = (kept, i)

    def require(self, *stems):
        for s in stems:
            if s in self.missing:
                raise Missing(self.missing[s])

    def keys(self, scenario=None, n_pilots=None):
        return [k for k in self.series if (scenario is None or k[0] == scenario)
                and (n_pilots is None or k[3] == n_pilots)]

    def label(self, scenario):
        """Each frame's true class id (recognition) or true delay index (delays)."""
        f = self.truth.frames[scenario]
        return f["delay_index"] if self.lower_is_better else f["class_id"]

    def scores(self, scenario, method, n_pilots, snr, mask=None):
        """{training seed (None: no training): per-frame score array} of the method at the point
        (every mask of it unless `mask` is given; a method on several masks needs one)."""
        out = OrderedDict()
        masks = set()
        for k, (kept, i) in self.series.items():
            if k[0] == scenario and k[1] == method and k[3] == n_pilots and k[4] == snr and (mask is None or k[2] == mask):
                masks.add(k[2])
                v = kept.values(i)
                if self.lower_is_better:
                    out[k[5]] = np.abs(v.astype(np.float64))
                else:
                    out[k[5]] = (v == self.truth.frames[scenario]["class_id"]).astype(np.float64)
        if len(masks) > 1:
            raise ValueError("%s at N_p %d runs on several masks (%s): name one" % (method, n_pilots, sorted(masks)))
        return out


def records(rows, dtype):
    """Structured records of several files as one array: each text field as wide as its widest."""
    fields = [(n, max([r.dtype[n] for r in rows] + [dtype[n]], key=lambda d: d.itemsize)) for n in dtype.names]
    return np.array([tuple(r.tolist()) for r in rows], dtype=fields)


def merge(out, inputs):
    """One kept file (predictions or truth) from the parts of a split run: the series of every
    input (a series in two inputs must be the same), or the scenarios of every truth file (a
    scenario in two must have the same frames)."""
    z0 = np.load(inputs[0], allow_pickle=False)
    info = z0["info"]
    truth = str(info["quantity"][0]) == "truth"
    members = OrderedDict()
    if truth:
        scenarios = []
        for path in inputs:
            with np.load(path, allow_pickle=False) as z:
                if z["info"]["experiment"][0] != info["experiment"][0]:
                    raise SystemExit("predictions.py merge: %s is of another experiment" % path)
                for r in z["scenarios"]:
                    name = str(r["scenario"])
                    for m in ("frames_", "classes_"):
                        if m + name in members and not np.array_equal(members[m + name], z[m + name]):
                            raise SystemExit("predictions.py merge: %s has other frames for %s" % (path, name))
                        members[m + name] = z[m + name]
                    if name not in [str(s["scenario"]) for s in scenarios]:
                        scenarios.append(r)
        arrays = OrderedDict([("info", info), ("scenarios", records(scenarios, z0["scenarios"].dtype))])
        arrays.update(members)
    else:
        series, rows, seen = [], [], {}
        for path in inputs:
            k = Kept(path)
            if (k.experiment, k.quantity, k.bits, k.n_frames) != (info["experiment"][0], info["quantity"][0],
                                                                 info["bits"][0], info["n_frames"][0]):
                raise SystemExit("predictions.py merge: %s has another experiment, quantity, packing or frame count "
                                 "than %s" % (path, inputs[0]))
            for i in range(len(k)):
                key = tuple(k.series[i].tolist())
                if key in seen:
                    if not np.array_equal(rows[seen[key]], k.raw[i]):
                        raise SystemExit("predictions.py merge: %s disagrees with an earlier input on %s" % (path, key))
                    continue
                seen[key] = len(rows)
                series.append(k.series[i])
                rows.append(k.raw[i])
        arrays = OrderedDict([("info", info),
                              ("series", records(series, z0["series"].dtype)),
                              ("values", np.array(rows, dtype=z0["values"].dtype).reshape(
                                  (len(rows),) + z0["values"].shape[1:]))])
    z0.close()
    save(out, arrays)
    print("predictions.py: wrote %s (%s from %d file%s)" % (
        out, "%d scenarios" % len(arrays["scenarios"]) if truth else "%d series" % len(arrays["series"]),
        len(inputs), "" if len(inputs) == 1 else "s"))


def save(path, arrays):
    """An .npz as sems_eval writes one: members stored, without time stamps (the same arrays
    give the same bytes), written to a temporary file and renamed over path."""
    tmp = path + ".tmp"
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_STORED) as z:
        for name, a in arrays.items():
            buf = io.BytesIO()
            np.lib.format.write_array(buf, np.asanyarray(a), allow_pickle=False)
            z.writestr(zipfile.ZipInfo(name + ".npy", date_time=(1980, 1, 1, 0, 0, 0)), buf.getvalue())
    os.replace(tmp, path)


def fmt6(v):
    """A value as sems_eval writes it in a CSV (6 significant digits, inf/nan spelled out)."""
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return "%.6g" % v


def recognition_scores(pred, truth, n_classes):
    """Accuracy and macro-F1 as sems_eval computes them (the same operations in the same order)."""
    tp = [0.0] * n_classes
    fp = [0.0] * n_classes
    fn = [0.0] * n_classes
    correct = 0
    for p, t in zip(pred.tolist(), truth.tolist()):
        if p == t:
            correct += 1
            tp[t] += 1
        else:
            if 0 <= p < n_classes:
                fp[p] += 1
            fn[t] += 1
    f1, present = 0.0, 0
    for k in range(n_classes):
        if tp[k] + fn[k] == 0:
            continue
        present += 1
        denom = 2 * tp[k] + fp[k] + fn[k]
        f1 += 2 * tp[k] / denom if denom > 0 else 0.0
    return correct / len(truth), (f1 / present if present else 0.0)


def delay_scores(err):
    """Mean, RMS and median absolute error and the fraction above half an index, as sems_eval
    computes them from the kept float32 errors (sums in frame order)."""
    mae = rmse = gross = 0.0
    a = []
    for e in err.astype(np.float64).tolist():
        a.append(abs(e))
        mae += abs(e)
        rmse += e * e
        gross += 1.0 if abs(e) > 0.5 else 0.0
    n = len(a)
    return mae / n, math.sqrt(rmse / n), sorted(a)[n // 2], gross / n


def check(results, experiments=None):
    """Every CSV row of experiments 1, 3, 4, 5, 7 and 9 (or those given) with a kept series,
    recomputed; returns (rows checked, list of differences, list of missing files)."""
    checked, problems, missing = 0, [], []
    for experiment in experiments or SOURCES:
        exp = Experiment(results, experiment)
        missing += list(exp.missing.values())
        for stem in exp.stems:
            for prefix in ("", "shipped_"):
                path = os.path.join(results, prefix + stem + ".csv")
                if not os.path.exists(path):
                    continue
                with open(path, newline="") as f:
                    for r in csv.DictReader(f):
                        if r["method"].startswith("CRB"):
                            continue  # a bound: no per-frame estimates
                        seed = None if r["train_seed"] == "none" else r["train_seed"]
                        key = (r["scenario"], r["method"], r.get("mask", ""), int(r["n_pilots"]), float(r["snr_db"]),
                               seed)
                        hit = [k for k in exp.series if k == key or (
                            "mask" not in r and k[:2] == key[:2] and k[3:] == key[3:])]
                        if len(hit) != 1:
                            problems.append("%s: no kept series for %s" % (path, key))
                            continue
                        kept, i = exp.series[hit[0]]
                        v = kept.values(i)
                        if exp.lower_is_better:
                            got = dict(zip(("mae_index", "rmse_index", "median_abs_error_index",
                                            "frac_error_over_half_index"), delay_scores(v)))
                        else:
                            acc, f1 = recognition_scores(v, exp.truth.frames[key[0]]["class_id"],
                                                         len(exp.truth.classes[key[0]]))
                            got = {"accuracy": acc, "macro_f1": f1}
                        checked += 1
                        for col, value in got.items():
                            if col in r and fmt6(value) != r[col] and float(fmt6(value)) != float(r[col]):
                                problems.append("%s: %s, %s: the CSV has %s, the kept series gives %s" % (
                                    path, key, col, r[col], fmt6(value)))
    return checked, problems, missing


def show(path):
    with np.load(path, allow_pickle=False) as z:
        if str(z["info"]["quantity"][0]) == "truth":
            t = Truth(path)
            print("%s: truth of experiment %s" % (path, t.info["experiment"]))
            for s, (seed, n) in t.scenarios.items():
                print("  %s: %d frames, test seed %d, classes %s" % (s, n, seed, ", ".join(t.classes[s])))
            return
    k = Kept(path)
    print("%s: experiment %s, %s, %d series of %d frames%s" % (
        path, k.experiment, k.quantity, len(k), k.n_frames, ", %d bits per id" % k.bits if k.bits else ""))
    groups = OrderedDict()
    for i in range(len(k)):
        key = k.key(i)
        groups.setdefault(key[:4], []).append((key[4], key[5]))
    for (scen, method, mask, np_), pts in groups.items():
        snrs = sorted({p[0] for p in pts})
        seeds = sorted({p[1] or "none" for p in pts})
        print("  %s | %s | %s | N_p %d: SNR %s dB, training seeds %s" % (
            scen, method, mask, np_, ", ".join("%g" % s for s in snrs), ", ".join(seeds)))


def main(argv):
    if len(argv) >= 2 and argv[0] == "show":
        for p in argv[1:]:
            show(p)
        return 0
    if len(argv) >= 3 and argv[0] == "merge":
        merge(argv[1], argv[2:])
        return 0
    if len(argv) in (2, 3) and argv[0] == "check":
        which = argv[2].split(",") if len(argv) == 3 else None
        if which and not set(which) <= set(SOURCES):
            print("predictions.py check: experiments are among %s, got %s" % (", ".join(SOURCES), argv[2]),
                  file=sys.stderr)
            return 2
        checked, problems, missing = check(argv[1], which)
        for m in missing:
            print("predictions.py check: %s" % m, file=sys.stderr)
        for p in problems[:20]:
            print("predictions.py check: %s" % p, file=sys.stderr)
        print("predictions.py check: %d CSV rows recomputed from the kept predictions, %d differ%s" % (
            checked, len(problems), "" if not missing else ", %d kept files missing" % len(missing)))
        return 1 if problems or not checked else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
