#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Combine a full sems_eval run that was split over processes into one set of CSVs.

    combine_runs.py RUNS_DIR RESULTS_DIR

RUNS_DIR holds the processes' output folders as docs/RESULTS.md runs them: full (experiment
1), full3 (experiment 3), full4 (experiment 4, single path), full4b (experiment 4,
multipath), shipped (the --only-shipped rows). Writes exp1_recognition.csv,
exp3_conditions.csv, exp4_delay.csv, shipped_exp1_recognition.csv, shipped_exp4_delay.csv
and exp6_cost.csv (the cost rows of experiments 1, 3 and 4, rebuilt from their CSVs: the
processes ran without experiment 6) into RESULTS_DIR. Fails if a part is missing or the
headers differ.
"""
import csv
import os
import sys

PARTS = {
    "exp1_recognition.csv": ["full"],
    "exp3_conditions.csv": ["full3"],
    "exp4_delay.csv": ["full4", "full4b"],
}
SHIPPED = {"shipped_exp1_recognition.csv": "exp1_recognition.csv", "shipped_exp4_delay.csv": "exp4_delay.csv"}
COST = ["experiment", "scenario", "method", "mask", "n_pilots", "snr_db", "metric", "value", "us_per_frame",
        "n_frames", "seed", "train_seed", "train_seconds"]


def read(path):
    if not os.path.exists(path):
        sys.exit("combine_runs: %s is missing" % path)
    with open(path, newline="") as f:
        r = csv.reader(f)
        return next(r), list(r)


def write(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    print("wrote %s (%d rows)" % (path, len(rows)))


def main(runs, out):
    for name, parts in PARTS.items():
        header, rows = None, []
        for p in parts:
            h, r = read(os.path.join(runs, p, name))
            if header is not None and h != header:
                sys.exit("combine_runs: %s/%s has another header" % (p, name))
            header, rows = h, rows + r
        write(os.path.join(out, name), header, rows)
    for name, source in SHIPPED.items():
        write(os.path.join(out, name), *read(os.path.join(runs, "shipped", source)))
    cost = []
    for name, metric in (("exp1_recognition.csv", "accuracy"), ("exp3_conditions.csv", "accuracy"),
                         ("exp4_delay.csv", "mae_index")):
        with open(os.path.join(out, name), newline="") as f:
            for r in csv.DictReader(f):
                cost.append([r["experiment"], r["scenario"], r["method"], r["mask"], r["n_pilots"], r["snr_db"],
                             metric, r[metric], r["us_per_frame"], r["n_frames"], r["seed"], r["train_seed"],
                             r["train_seconds"]])
    write(os.path.join(out, "exp6_cost.csv"), COST, cost)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
