#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The link-budget scene's SNR against range per class, from the module's own radar equation
(gr::sems::link_budget::snr_db, through the Python bindings) on the frame the scene is for.

    link_budget_table.py SOURCE_DIR            print the table (Markdown)
    link_budget_table.py SOURCE_DIR --write    put it into docs/reference/link_budget.md
    link_budget_table.py SOURCE_DIR --check    exit 1 if that page's table is out of date

The page holds the table between the lines `<!-- budget -->` and `<!-- /budget -->`.
"""
import argparse
import json
import os
import sys

from gnuradio import sems

BEGIN, END = "<!-- budget -->", "<!-- /budget -->"
SCENE = os.path.join("models", "scenes", "kinematic_sdr_budget.json")
FRAME = "sdr_2g4_20mhz"
RANGES_M = [5, 10, 20, 50, 100, 200]


def db(x):
    text = f"{x:.1f}"
    return "0.0" if text == "-0.0" else text


def table(source):
    sc = sems.scene.load(os.path.join(source, SCENE))
    fs = sems.frame_file.find(FRAME).frame
    b = sc.budget()
    lib = json_library(sc)
    head = "| class | RCS (dBsm) | " + " | ".join(f"{r} m" for r in RANGES_M) + " |"
    rows = [f"SNR per resource element in dB at the budget's thermal noise (the emulator's SNR setting 0 dB), "
            f"`{SCENE}` on the `{FRAME}` frame ({fs.carrier_hz / 1e9:g} GHz, {fs.bandwidth_hz / 1e6:g} MHz): "
            f"{b.tx_power_dbm:g} dBm, {b.tx_gain_dbi:g} + {b.rx_gain_dbi:g} dBi, noise figure {b.noise_figure_db:g} dB, "
            f"losses {b.system_loss_db:g} dB, T_0 {b.noise_temperature_k:g} K. Each cell: the class's RCS interval's "
            "low end to its high end; ranges outside a class's interval are left blank.", "",
            head, "|---|---|" + "---|" * len(RANGES_M)]
    for c in lib["classes"]:
        lo, hi = c["rcs_dbsm"] if isinstance(c["rcs_dbsm"], list) else [c["rcs_dbsm"]] * 2
        r_lo, r_hi = c["range_m"] if isinstance(c["range_m"], list) else [c["range_m"]] * 2
        cells = []
        for r in RANGES_M:
            if r < r_lo or r > r_hi:
                cells.append("")
            else:
                cells.append(f"{db(b.snr_db(fs, r, lo))} to {db(b.snr_db(fs, r, hi))}")
        rows.append(f"| {c['name']} | {lo:g} to {hi:g} | " + " | ".join(cells) + " |")
    return "\n".join(rows) + "\n"


def json_library(sc):
    return json.loads(sc.library().to_json())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("source")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true")
    g.add_argument("--check", action="store_true")
    a = ap.parse_args()
    page = os.path.join(a.source, "docs", "reference", "link_budget.md")
    t = table(a.source)
    if not (a.write or a.check):
        sys.stdout.write(t)
        return
    text = open(page).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"{page}: no {BEGIN} ... {END} lines to hold the table")
    before, rest = text.split(BEGIN, 1)
    after = rest.split(END, 1)[1]
    new = before + BEGIN + "\n" + t + END + after
    if a.check:
        if new != text:
            sys.exit(f"{page}: the link-budget table is out of date; run scripts/link_budget_table.py {a.source} --write")
        return
    open(page, "w").write(new)


if __name__ == "__main__":
    main()
