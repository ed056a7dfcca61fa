#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The table of frame presets, computed from the preset files (models/frames/*.json).

    frame_presets_table.py SOURCE_DIR            print the table (Markdown)
    frame_presets_table.py SOURCE_DIR --write    put it into docs/reference/frame_files.md
    frame_presets_table.py SOURCE_DIR --check    exit 1 if that page's table is out of date

The page holds the table between the lines `<!-- presets -->` and `<!-- /presets -->`.
"""
import argparse
import glob
import json
import os
import sys

C = 3e8  # the module's speed of light (docs/design.md §1)
BEGIN, END = "<!-- presets -->", "<!-- /presets -->"
ORDER = ["paper", "sdr_2g4_20mhz", "wifi_5g_80mhz", "nr_30khz", "nr_sensing_120khz", "auto_77g"]


def guards(frame):
    count = 0
    for g in frame.get("guard_subcarriers", []):
        count += g[1] - g[0] + 1 if isinstance(g, list) else 1
    return count


def num(x, digits=4):
    return f"{x:.{digits}g}"


def array(source, name):
    """The array preset a frame names: its name, element counts and spacing."""
    if not name:
        return ""
    a = json.load(open(os.path.join(source, "models", "arrays", name + ".json")))
    def side(s):
        g = a[s]
        if "ula" in g:
            return g["ula"]["elements"], f"{num(g['ula']['spacing_m'] * 1e3)} mm"
        if "ura" in g:
            u = g["ura"]
            return u["columns"] * u["rows"], f"{u['columns']} × {u['rows']}, {num(u['spacing_m'][0] * 1e3)} mm"
        return len(g["positions_m"]), "positions"
    rx, rx_layout = side("receive")
    text = f"`{name}`: {rx} receive ({rx_layout})"
    if "transmit" in a:
        tx, tx_layout = side("transmit")
        text += f", {tx} transmit ({tx_layout})"
    return text


def table(source):
    files = glob.glob(os.path.join(source, "models", "frames", "*.json"))
    presets = [json.load(open(f)) for f in files]
    presets.sort(key=lambda p: (ORDER.index(p["name"]) if p["name"] in ORDER else len(ORDER), p["name"]))
    rows = ["| preset | N × M (used) | B | f_c | Δf | T | CP | unambiguous range | unambiguous speed | classes | array |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in presets:
        f = p["frame"]
        n, m = f["n_symbols"], f["n_subcarriers"]
        b, fc, t = f["bandwidth_hz"], f["carrier_hz"], f["symbol_interval_s"]
        df = b / m
        rows.append(
            f"| `{p['name']}` | {n} × {m} ({m - guards(f)}) | {num(b / 1e6)} MHz | {num(fc / 1e9)} GHz "
            f"| {num(df / 1e3)} kHz | {num(t * 1e3)} ms | {f['cp_len']} | {num(C / (2 * df))} m "
            f"| ±{num(C / fc / (4 * t), 3)} m/s | `{p.get('classes', '')}` | {array(source, p.get('array', ''))} |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("source")
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    t = table(a.source)
    if not (a.write or a.check):
        print(t)
        return
    page = os.path.join(a.source, "docs", "reference", "frame_files.md")
    text = open(page).read()
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    new = f"{head}{BEGIN}\n{t}\n{END}{tail}"
    if a.check:
        if new != text:
            sys.exit(f"{page}: the presets table is out of date; run {sys.argv[0]} {a.source} --write")
        return
    open(page, "w").write(new)


if __name__ == "__main__":
    main()
