#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Combine a full sems_eval run that was split over processes into one set of CSVs.

    combine_runs.py RUNS_DIR RESULTS_DIR

RUNS_DIR holds the processes' output folders as scripts/evaluation/eval_full.sh runs them: full
(experiments 1 and 2, part of 5), full4 (experiment 4 single path, experiment 3, part of 5),
full4b (experiment 4 multipath, the rest of 5), shipped (the --only-shipped rows); each of the
first three also wrote the cost rows of its own experiments (experiment 6). Experiment 5's
rows are put back in the sweep's order (N_p, training seed, SNR). Writes exp1_recognition.csv,
exp2_tsne_features.csv, exp3_conditions.csv, exp4_delay.csv, exp5_pilot_budget.csv,
exp6_cost.csv, shipped_exp1_recognition.csv and shipped_exp4_delay.csv into RESULTS_DIR.
Fails if a part is missing or the headers differ.
"""
import csv
import os
import sys

PARTS = {
    "exp1_recognition.csv": ["full"],
    "exp2_tsne_features.csv": ["full"],
    "exp3_conditions.csv": ["full4"],
    "exp4_delay.csv": ["full4", "full4b"],
    "exp5_pilot_budget.csv": ["full", "full4", "full4b"],
    "exp6_cost.csv": ["full", "full4", "full4b"],
}
# Rows of a sweep split over parts are sorted by these numeric columns (stable).
SORT_BY = {"exp5_pilot_budget.csv": ["n_pilots", "train_seed", "snr_db"]}
SHIPPED = {"shipped_exp1_recognition.csv": "exp1_recognition.csv", "shipped_exp4_delay.csv": "exp4_delay.csv"}


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
        if name in SORT_BY:  # parts that split one sweep: back in the sweep's order
            cols = [header.index(c) for c in SORT_BY[name]]
            rows.sort(key=lambda row: [float(row[c]) for c in cols])
        write(os.path.join(out, name), header, rows)
    for name, source in SHIPPED.items():
        write(os.path.join(out, name), *read(os.path.join(runs, "shipped", source)))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
