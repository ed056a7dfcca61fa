#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: cost against frame size, from 8 x 64 (the paper's 32 x 64 among them) to 256 x 4 096.

Runs the module's own benchmarks at growing frame sizes and writes one CSV, a Markdown
table generated from it and a figure:

- emulator: sems_bench_channel at N x M, ns per resource element of target_channel (one
  path with noise, ten paths, a walker), each row next to blocks.multiply_const_vcc on the
  same vector size measured in the same run (the anchor);
- training: sems_train (classifier, two epochs of mask+task and one decoder epoch), frames
  per CPU second of the second mask+task epoch and the process's peak memory, against N x M;
- decoders and sinks: bundle_decoder and the sink (sems_bench_sinks) on small bundles trained
  at each (N, M, N_p), frames/s per batch size; at the paper's frame over --steady-frames
  frames (the steady state), elsewhere over fewer.

Figures are per CPU second where the harness gives them (all threads of the process: on a
shared machine the wall clock measures the neighbours too); the CSV keeps both.

Usage:
    sems_bench_scaling.py --bin build/apps --out DIR [--quick]
    sems_bench_scaling.py --table DIR/scaling.csv > scaling_tables.md
    sems_bench_scaling.py --plot DIR/scaling.csv scaling.png
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import time

FIELDS = ["part", "name", "n_symbols", "n_subcarriers", "n_pilots", "batch", "frames",
          "wall", "cpu", "unit", "anchor_wall", "anchor_cpu", "peak_mib"]

# (N, M) of the emulator rows; (N, M, N_p, training frames) of the training rows;
# (N, M, N_p) of the sink rows.
FULL = {
    "emulator": [(32, 64), (32, 256), (32, 1024), (32, 4096), (8, 64), (128, 64), (256, 4096)],
    # At least two full batches of 256 training frames per epoch (80 % of the frames train):
    # shorter epochs time the start-up.
    "training": [(32, 64, 32, 2000), (32, 256, 32, 700), (32, 1024, 128, 700), (64, 1024, 128, 700),
                 (14, 4096, 128, 700)],
    "sinks": [(32, 64, 32), (32, 64, 128), (32, 1024, 128), (32, 1024, 1024), (256, 4096, 1024)],
}
QUICK = {  # one small size each: checks that every part runs and parses
    "emulator": [(8, 64)],
    "training": [(8, 64, 16, 100)],
    "sinks": [(8, 64, 16)],
}
EMULATOR_ROWS = {  # sems_bench_channel row name -> our short name
    "target_channel,  1 path,  SNR 20 dB": "1 path, noise",
    "target_channel, 10 paths, SNR 20 dB": "10 paths, noise",
    "target_channel, walker (16 segments), SNR 20 dB": "walker, noise",
}
ANCHOR_ROW = "blocks.multiply_const_vcc"


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def run(cmd, what):
    """Runs cmd, shows how long it took; returns its standard output."""
    t0 = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"sems_bench_scaling: {what} failed (exit {proc.returncode}): {' '.join(cmd)}\n{proc.stderr[-2000:]}")
    log(f"  {what}: {time.time() - t0:.1f} s")
    return proc.stdout


def emulator_rows(binary, n, m, seconds, repeat):
    out = run([binary, "--symbols", str(n), "--subcarriers", str(m), "--seconds", str(seconds),
                  "--repeat", str(repeat)], f"emulator {n} x {m}")
    table = {}
    for line in out.splitlines():
        # a 52-character name, then symbols/s, samples/s, vs mult., symbols/CPU-s, vs mult.
        name, cells = line[:52].strip(), line[52:].split()
        if len(cells) == 5 and (name == ANCHOR_ROW or name in EMULATOR_ROWS):
            table[name] = (float(cells[0]), float(cells[3]))
    if ANCHOR_ROW not in table:
        sys.exit(f"sems_bench_scaling: no {ANCHOR_ROW} row in the output of {binary}")
    anchor = table[ANCHOR_ROW]
    rows = []
    for full, short in EMULATOR_ROWS.items():
        if full not in table:
            sys.exit(f"sems_bench_scaling: no '{full}' row in the output of {binary}")
        wall, cpu = table[full]
        ns = lambda rate: 1e9 / (rate * m)  # symbols/s -> ns per resource element
        rows.append(dict(part="emulator", name=short, n_symbols=n, n_subcarriers=m, n_pilots="", batch="",
                         frames="", wall=ns(wall), cpu=ns(cpu), unit="ns/RE", anchor_wall=ns(anchor[0]),
                         anchor_cpu=ns(anchor[1]), peak_mib=""))
    return rows


def training_rows(binary, work, n, m, np_, frames):
    # Two mask+task epochs, the second timed: the first also pays the process's start-up (at the
    # paper's frame a quarter of a short epoch).
    cmd = [binary, "--task", "classify", "--symbols", str(n), "--subcarriers", str(m), "--pilots", str(np_),
           "--frames", str(frames), "--epochs", "2", "--decoder-epochs", "1", "--threads", "1", "--seed", "1",
           "--out", os.path.join(work, f"train_{n}x{m}_np{np_}")]
    t0 = time.time()
    proc = subprocess.run(["/usr/bin/time", "-f", "peak_kib %M cpu_s %U %S"] + cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"sems_bench_scaling: training {n} x {m} failed: {' '.join(cmd)}\n{proc.stderr[-2000:]}")
    log(f"  train {n} x {m}, N_p {np_}, {frames} frames: {time.time() - t0:.1f} s")
    epoch = re.search(r"epoch +2 \[mask\+task\].*?([0-9.]+) s +([0-9.]+) frames/s +([0-9.]+) CPU-s", proc.stdout)
    peak = re.search(r"peak_kib (\d+)", proc.stderr)
    if not epoch or not peak:
        sys.exit(f"sems_bench_scaling: could not read the epoch rate or the peak memory of: {' '.join(cmd)}")
    train_frames = int(re.search(r"data: (\d+) train", proc.stdout).group(1))
    # The epoch's frames (whole batches of 256) over its wall and its CPU seconds (the log gives
    # tenths: an epoch under 0.05 CPU-s, as --quick's, has no CPU rate).
    epoch_frames = float(epoch.group(2)) * float(epoch.group(1))
    cpu_s = float(epoch.group(3))
    return [dict(part="training", name="mask+task epoch", n_symbols=n, n_subcarriers=m, n_pilots=np_, batch="",
                 frames=train_frames, wall=float(epoch.group(2)), cpu=epoch_frames / cpu_s if cpu_s > 0 else "",
                 unit="frames/s", anchor_wall="", anchor_cpu="", peak_mib=int(peak.group(1)) / 1024.0)]


def sink_rows(train_bin, sinks_bin, work, n, m, np_, batches, frames):
    rows = []
    for task in ("classify", "delay"):
        bundle = os.path.join(work, f"sink_{task}_{n}x{m}_np{np_}")
        if not os.path.exists(os.path.join(bundle, "bundle.json")):
            cmd = [train_bin, "--task", task, "--symbols", str(n), "--subcarriers", str(m), "--pilots", str(np_),
                   "--frames", "40", "--epochs", "1", "--decoder-epochs", "0", "--threads", "1", "--seed", "1",
                   "--out", bundle]
            run(cmd, f"tiny {task} bundle {n} x {m}, N_p {np_}")
        flag = "--classifier" if task == "classify" else "--delay"
        out = run([sinks_bin, flag, bundle, "--threads", "1", "--batches", ",".join(map(str, batches)),
                      "--frames", str(frames)], f"{task} decoder and sink {n} x {m}, N_p {np_}, {frames} frames")
        for line in out.splitlines():
            cells = line.split()
            if len(cells) == 7 and cells[0] == bundle:
                batch, nf, dec_wall, sink_wall, dec_cpu, sink_cpu = (int(cells[1]), int(cells[2]), *map(float, cells[3:]))
                common = dict(n_symbols=n, n_subcarriers=m, n_pilots=np_, batch=batch, frames=nf, unit="frames/s",
                              peak_mib="")
                rows.append(dict(part="sinks", name=f"{task} decoder", wall=dec_wall, cpu=dec_cpu, anchor_wall="",
                                 anchor_cpu="", **common))
                rows.append(dict(part="sinks", name=f"{task} sink", wall=sink_wall, cpu=sink_cpu,
                                 anchor_wall=dec_wall, anchor_cpu=dec_cpu, **common))
    return rows


def measure(args):
    sizes = QUICK if args.quick else FULL
    tool = lambda name: os.path.join(args.bin, name)
    os.makedirs(args.out, exist_ok=True)
    work = os.path.join(args.out, "bundles")
    os.makedirs(work, exist_ok=True)
    rows = []
    seconds, repeat = (0.05, 1) if args.quick else (args.seconds, args.repeat)
    parts = args.parts.split(",")
    log(f"emulator: {len(sizes['emulator'])} frame sizes")
    for n, m in sizes["emulator"] if "emulator" in parts else []:
        rows += emulator_rows(tool("sems_bench_channel"), n, m, seconds, repeat)
    path = os.path.join(args.out, "scaling.csv")
    save(path, rows)
    log(f"training: {len(sizes['training'])} frame sizes")
    for n, m, np_, frames in sizes["training"] if "training" in parts else []:
        rows += training_rows(tool("sems_train"), work, n, m, np_, frames)
    save(path, rows)
    log(f"decoders and sinks: {len(sizes['sinks'])} sizes")
    batches = [1, 4] if args.quick else [1, 32, 256]
    for n, m, np_ in sizes["sinks"] if "sinks" in parts else []:
        steady = (n, m) == (32, 64) and not args.quick
        frames = args.steady_frames if steady else (64 if args.quick else max(2048, args.steady_frames // 10))
        rows += sink_rows(tool("sems_train"), tool("sems_bench_sinks"), work, n, m, np_, batches, frames)
        save(path, rows)
    log(f"sems_bench_scaling: {len(rows)} rows in {path}")
    return path


def save(path, rows):
    """Writes the rows measured so far (a long run keeps what it has measured)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(x):
    return float(x) if x not in ("", None) else float("nan")


def table(path):
    rows = read(path)
    out = ["<!-- generated by apps/benchmarks/sems_bench_scaling.py --table from its scaling.csv: do not edit -->", ""]
    emu = [r for r in rows if r["part"] == "emulator"]
    if emu:
        base = {r["name"]: num(r["cpu"]) for r in emu if (r["n_symbols"], r["n_subcarriers"]) == ("32", "64")}
        out += ["### Emulator: ns per resource element (CPU time), target_channel with noise", "",
                "| N × M | " + " | ".join(f"{k} | vs 32 × 64" for k in EMULATOR_ROWS.values())
                + " | multiply_const_vcc (anchor) |",
                "|---" * (2 * len(EMULATOR_ROWS) + 2) + "|"]
        sizes = sorted({(int(r["n_symbols"]), int(r["n_subcarriers"])) for r in emu}, key=lambda s: (s[1], s[0]))
        for n, m in sizes:
            cells = [f"{n} × {m}"]
            anchor = float("nan")
            for name in EMULATOR_ROWS.values():
                r = next(r for r in emu if (int(r["n_symbols"]), int(r["n_subcarriers"]), r["name"]) == (n, m, name))
                cells += [f"{num(r['cpu']):.1f}", f"{num(r['cpu']) / base.get(name, float('nan')):.2f}×"]
                anchor = num(r["anchor_cpu"])
            cells.append(f"{anchor:.2f}")
            out.append("| " + " | ".join(cells) + " |")
        out.append("")
    tr = [r for r in rows if r["part"] == "training"]
    if tr:
        ref = next((r for r in tr if (r["n_symbols"], r["n_subcarriers"]) == ("32", "64")), None)
        # Frames per CPU second where the run recorded them (the neighbours on a shared machine
        # do not move them), else per wall second.
        col = "cpu" if all(r["cpu"] for r in tr) else "wall"
        out += ["### Training: classifier, the second mask+task epoch, one thread", "",
                f"| N × M | N_p | training frames | frames per {'CPU ' if col == 'cpu' else ''}second | "
                "× (N·M) vs 32 × 64 | peak memory (MiB) |",
                "|---|---|---|---|---|---|"]
        for r in tr:
            nm = int(r["n_symbols"]) * int(r["n_subcarriers"])
            rel = ""
            if ref:
                # frames/s times N·M, relative to the paper's frame: 1.00 = cost grows as N·M, > 1 slower.
                rel = f"{(num(ref[col]) * 32 * 64) / (num(r[col]) * nm):.2f}"
            out.append(f"| {r['n_symbols']} × {r['n_subcarriers']} | {r['n_pilots']} | {r['frames']} | "
                       f"{num(r[col]):.1f} | {rel} | {num(r['peak_mib']):.0f} |")
        out += ["", "The × (N·M) column is the cost per resource element against the paper's frame: 1.00 means "
                "the time per frame grows exactly as N·M, above 1 faster.", ""]
    si = [r for r in rows if r["part"] == "sinks"]
    if si:
        out += ["### Decoders and sinks: frames/s per CPU second, one intra-op thread", "",
                "| task | N × M | N_p | batch | frames | decoder | sink | sink / decoder |",
                "|---|---|---|---|---|---|---|---|"]
        for r in si:
            if not r["name"].endswith("sink"):
                continue
            task = r["name"].split()[0]
            out.append(f"| {task} | {r['n_symbols']} × {r['n_subcarriers']} | {r['n_pilots']} | {r['batch']} | "
                       f"{r['frames']} | {num(r['anchor_cpu']):.0f} | {num(r['cpu']):.0f} | "
                       f"{num(r['cpu']) / num(r['anchor_cpu']):.2f} |")
        out.append("")
    print("\n".join(out))


def plot(path, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = read(path)
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    emu = [r for r in rows if r["part"] == "emulator" and r["n_symbols"] == "32"]
    for name in EMULATOR_ROWS.values():
        pts = sorted((int(r["n_subcarriers"]), num(r["cpu"])) for r in emu if r["name"] == name)
        ax[0].plot(*zip(*pts), "o-", label=name) if pts else None
    anchor = sorted({(int(r["n_subcarriers"]), num(r["anchor_cpu"])) for r in emu})
    if anchor:
        ax[0].plot(*zip(*anchor), "k--", label="multiply_const_vcc (anchor)")
    ax[0].set(xscale="log", yscale="log", xlabel="subcarriers M (N = 32)", ylabel="ns per resource element (CPU)",
              title="Emulator")
    if emu:
        ax[0].legend(fontsize=8)
    tr = sorted((r for r in rows if r["part"] == "training"), key=lambda r: int(r["n_symbols"]) * int(r["n_subcarriers"]))
    if tr:
        nm = [int(r["n_symbols"]) * int(r["n_subcarriers"]) for r in tr]
        col = "cpu" if all(r["cpu"] for r in tr) else "wall"  # as the table
        fps = [num(r[col]) for r in tr]
        ax[1].plot(nm, fps, "o-", label="measured")
        ideal = [fps[0] * nm[0] / x for x in nm]
        ax[1].plot(nm, ideal, "k--", label="∝ 1/(N·M) from 32 × 64")
        for x, y, r in zip(nm, fps, tr):
            ax[1].annotate(f"{r['n_symbols']}×{r['n_subcarriers']}\n{num(r['peak_mib']):.0f} MiB", (x, y),
                           fontsize=7, textcoords="offset points", xytext=(4, 4))
        ax[1].set(xscale="log", yscale="log", xlabel="resource elements N·M",
                  ylabel="training frames per CPU second" if col == "cpu" else "training frames/s",
                  title="Training (classifier, 1 thread)")
        ax[1].legend(fontsize=8)
    si = [r for r in rows if r["part"] == "sinks" and r["name"].endswith("sink")]
    for task, marker in (("classify", "o"), ("delay", "s")):
        for batch in sorted({int(r["batch"]) for r in si}):
            pts = sorted((int(r["n_pilots"]) * 1.0, num(r["cpu"])) for r in si
                         if r["name"].startswith(task) and int(r["batch"]) == batch and r["n_subcarriers"] in ("64", "1024"))
            if pts:
                ax[2].plot(*zip(*pts), marker + "-", label=f"{task} sink, batch {batch}")
    if si:
        ax[2].set(xscale="log", yscale="log", xlabel="pilots N_p", ylabel="frames/s (CPU)", title="Sinks")
        ax[2].legend(fontsize=7)
    else:
        ax[2].set_axis_off()
        ax[2].text(0.5, 0.5, "sinks: not measured in this run (--parts)", ha="center", va="center")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument("--bin", help="directory of sems_bench_channel, sems_train, sems_bench_sinks")
    p.add_argument("--out", help="directory for scaling.csv and the small bundles")
    p.add_argument("--quick", action="store_true", help="tiny sizes (checks the tool runs; the figures mean nothing)")
    p.add_argument("--parts", default="emulator,training,sinks",
                   help="comma-separated parts to measure (default: all three)")
    p.add_argument("--seconds", type=float, default=1.0, help="emulator: seconds per row and run")
    p.add_argument("--repeat", type=int, default=3, help="emulator: runs per row (the best is kept)")
    p.add_argument("--steady-frames", type=int, default=100000,
                   help="sinks at the paper's frame: frames per batch size (the steady state)")
    p.add_argument("--table", metavar="CSV", help="print the Markdown tables of a scaling.csv")
    p.add_argument("--plot", nargs=2, metavar=("CSV", "PNG"), help="draw the figure of a scaling.csv")
    args = p.parse_args()
    if args.table:
        table(args.table)
    elif args.plot:
        plot(*args.plot)
    else:
        if not args.bin or not args.out:
            p.error("give --bin and --out (or --table / --plot)")
        for t in ("sems_bench_channel", "sems_train", "sems_bench_sinks"):
            if not os.access(os.path.join(args.bin, t), os.X_OK):
                p.error(f"--bin {args.bin}: no executable {t} there")
        if args.seconds <= 0 or not math.isfinite(args.seconds):
            p.error("--seconds must be a finite number > 0")
        if not args.parts or any(x not in ("emulator", "training", "sinks") for x in args.parts.split(",")):
            p.error(f"--parts {args.parts}: give a comma-separated list of emulator, training, sinks")
        if args.repeat < 1 or args.steady_frames < 1:
            p.error("--repeat and --steady-frames must be >= 1")
        measure(args)


if __name__ == "__main__":
    main()
