#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""sems_pareto: the decoders' speed/accuracy front.

For each task a sweep of decoder sizes, every network trained by sems_train decoder-only on
the same fixed mask (the shipped accurate bundle's), with the same budget and seed, then
scored by sems_pareto_eval on the same fresh test frames and timed on one thread at batch
1, 32 and 256, next to the classical methods (feature SVM; periodogram, OMP, LS) on the
same mask. Phases (all by default):
  train  sems_train per sweep point into BUNDLES/NAME (skipped when the bundle exists),
         each run's log in OUT/logs/train_NAME.log;
  eval   sems_pareto_eval -> OUT/classify.csv and OUT/delay.csv (rewritten), log OUT/logs/eval.log;
  plot   OUT/pareto.png (matplotlib) and OUT/pareto.md (the table).
Run from the source tree with a build in build/:
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE nice /usr/bin/python3 apps/evaluation/sems_pareto.py --out docs/pareto
"""
import argparse
import csv
import os
import subprocess
import sys
import time

# Budgets: the same for every network of a task (the accurate bundles' recipes, smaller). The
# shipped classifier and classifier_fast, which the sweep stands beside, have no tone/chirp fit
# (--chirp-bins 0): the sweep measures those decoders.
CLASSIFY = dict(mask="models/classifier/mask.json", scene_from="models/classifier",
                common=["--task", "classify", "--snr-min", "0", "--snr-max", "20", "--frames", "10000",
                        "--epochs", "4", "--threads", "1", "--seed", "1", "--eval-snr", "0,10,30", "--chirp-bins", "0",
                        "--quiet"])
DELAY = dict(mask="models/masks/one_symbol_random32.json", scene_from="models/delay_single",
             common=["--task", "delay", "--paths", "1", "--snr-min", "10", "--snr-max", "30", "--frames", "8000",
                     "--epochs", "4", "--lr", "0.003", "--threads", "1", "--seed", "1", "--eval-snr", "0,10,30",
                     "--quiet"])

# Sweep points: name -> sems_train size options. The first of each is the accurate bundle's
# architecture at the sweep's budget (the classifier's sizes and range gate; its convolutions
# take sems_train's default leaky ReLU, conv_slope 0.1, where the shipped classifier has 0).
CLASSIFY_SWEEP = [
    ("spectral_w16_h64_k64", ["--width", "16", "--hidden", "64", "--doppler-bins", "64"]),
    ("spectral_w4_h16_k32", ["--width", "4", "--hidden", "16", "--doppler-bins", "32"]),
    ("spectral_w8_h32_k32", ["--width", "8", "--hidden", "32", "--doppler-bins", "32"]),
    ("spectral_w2_h8_k32", ["--width", "2", "--hidden", "8", "--doppler-bins", "32"]),
    ("spectral_w8_h32_k64", ["--width", "8", "--hidden", "32", "--doppler-bins", "64"]),
    ("spectral_w16_h64_k32", ["--width", "16", "--hidden", "64", "--doppler-bins", "32"]),
    ("spectral_w32_h128_k64", ["--width", "32", "--hidden", "128", "--doppler-bins", "64"]),
    ("resnet_w8_d1_h32", ["--classifier", "resnet", "--width", "8", "--depth", "1", "--hidden", "32"]),
    ("resnet_w16_d2_h64", ["--classifier", "resnet", "--width", "16", "--depth", "2", "--hidden", "64"]),
]
DELAY_SWEEP = [
    ("delay_w16_d6_s0.125", ["--width", "16", "--depth", "6", "--delay-spacing", "0.125"]),
    ("delay_w8_d4_s0.25", ["--width", "8", "--depth", "4", "--delay-spacing", "0.25"]),
    ("delay_w4_d4_s0.5", ["--width", "4", "--depth", "4", "--delay-spacing", "0.5"]),
    ("delay_w8_d6_s0.25", ["--width", "8", "--depth", "6", "--delay-spacing", "0.25"]),
    ("delay_w16_d6_s0.25", ["--width", "16", "--depth", "6", "--delay-spacing", "0.25"]),
    ("delay_w4_d3_s0.5", ["--width", "4", "--depth", "3", "--delay-spacing", "0.5"]),
]


def run(cmd, log, env=None):
    t0 = time.time()
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
        f.write("# exit %d, %.1f s wall\n" % (rc, time.time() - t0))
    if rc != 0:
        sys.exit("sems_pareto: %s failed (exit %d), see %s" % (cmd[0], rc, log))
    return time.time() - t0


def train(args, task, sweep):
    for name, opts in sweep:
        if args.only and name not in args.only:
            continue
        out = os.path.join(args.bundles, name)
        if os.path.exists(os.path.join(out, "bundle.json")):
            continue
        cmd = [os.path.join(args.build, "apps", "sems_train")] + task["common"] + ["--mask", task["mask"]] + opts + \
            ["--out", out]
        s = run(cmd, os.path.join(args.out, "logs", "train_%s.log" % name))
        print("trained %s in %.0f s" % (name, s), flush=True)


def evaluate(args, tname, task, sweep, shipped, extra):
    path = os.path.join(args.out, tname + ".csv")
    if os.path.exists(path):
        os.remove(path)
    log = os.path.join(args.out, "logs", "eval.log")
    ev = os.path.join(args.build, "apps", "sems_pareto_eval")
    base = [ev, "--task", tname, "--scene-from", task["scene_from"], "--frames", str(args.frames),
            "--speed-frames", str(args.speed_frames), "--repeat", str(args.repeat), "--csv", path]
    run(base + ["--bundle", shipped, "--label", "shipped " + os.path.basename(shipped)] + extra, log)
    for name, _ in sweep:
        d = os.path.join(args.bundles, name)
        if os.path.exists(os.path.join(d, "bundle.json")):
            run(base + ["--bundle", d, "--label", name] + extra, log)
    for d in args.fast:
        if os.path.exists(os.path.join(d, "bundle.json")) and os.path.basename(d).startswith(shipped.split("/")[-1] + "_"):
            run(base + ["--bundle", d, "--label", "shipped " + os.path.basename(d)] + extra, log)
    run(base + ["--baselines", "--mask", task["mask"]], log)
    print("evaluated %s -> %s" % (tname, path), flush=True)


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def header(args):
    """What the table is, how it was made and on which frames: the page says it, not a notes file."""
    frames, evals = set(), []
    for tname in ("classify", "delay"):
        path = os.path.join(args.out, tname + ".csv")
        if os.path.exists(path):
            frames |= {int(r["frames"]) for r in read(path)}
    log = os.path.join(args.out, "logs", "eval.log")
    if os.path.exists(log):
        evals = [line[2:].strip() for line in open(log) if line.startswith("$ ")]
    repeat = evals[0].split("--repeat ")[1].split()[0] if evals and "--repeat " in evals[0] else str(args.repeat)
    return ["# The decoders' speed against accuracy", "",
            "Generated by `apps/evaluation/sems_pareto.py` (do not edit), from the shipped bundles and a sweep of",
            "decoder sizes trained by `sems_train` decoder-only on the shipped accurate bundle's mask, with the",
            "classical methods on the same pilots:", "", "<!-- excerpt -->",
            "    OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE nice /usr/bin/python3 apps/evaluation/sems_pareto.py --out docs/pareto --phases train",
            "    OMP_NUM_THREADS=1 OMP_WAIT_POLICY=PASSIVE nice /usr/bin/python3 apps/evaluation/sems_pareto.py --out docs/pareto --phases eval,plot --repeat %s" % repeat,
            "",
            "Every row is scored on the same %s fresh frames per SNR of the bundle's scene" % " / ".join(
                "{:,}".format(n).replace(",", " ") for n in sorted(frames)),
            "(`qa_learning_shipped`'s seed, which no training uses; each row's command is in `logs/eval.log`,",
            "each training's in `logs/train_*.log`): accuracy in % (classify) or the mean |error| in delay index",
            "(delay). Speed: frames per CPU-second on one thread at batch 1, 32 and 256, the fastest of %s runs," % repeat,
            "all rows in one run on a 2-core machine shared with other work: compare rows, not absolute rates,",
            "and read small ratios as ties. The figure to cite for a shipped bundle is its model card's",
            "([models](../../models/README.md)), on the test set the card records.", "",
            "![speed against accuracy](pareto.png)", ""]


def plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tasks = [("classify", "accuracy", "accuracy (%)"), ("delay", "mae_index", "MAE (delay index, log)")]
    snrs = ["0", "10", "30"]
    fig, axes = plt.subplots(2, 3, figsize=(17, 9))
    cmap = plt.get_cmap("tab20")
    md = ["| task | method | " + " | ".join("%s dB" % s for s in snrs) +
          " | frames/s b1 | b32 | b256 | latency b1 (ms) | latency b32 (ms) |", "|---" * 10 + "|"]
    for row, (tname, metric, ylabel) in enumerate(tasks):
        path = os.path.join(args.out, tname + ".csv")
        if not os.path.exists(path):
            continue
        rows = read(path)
        methods = []
        for r in rows:
            if r["method"] not in methods:
                methods.append(r["method"])
        for m in methods:
            rs = {r["snr_db"]: r for r in rows if r["method"] == m}
            r0 = next(iter(rs.values()))
            val = lambda s: float(rs[s][metric]) * (100 if metric == "accuracy" else 1) if s in rs else float("nan")
            md.append("| %s | %s | %s | %.0f | %.0f | %.0f | %.3f | %.3f |" % (
                tname, m, " | ".join(("%.1f" if metric == "accuracy" else "%.4f") % val(s) for s in snrs),
                float(r0["fps_cpu_b1"]), float(r0["fps_cpu_b32"]), float(r0["fps_cpu_b256"]),
                float(r0["latency_ms_b1"]), float(r0["latency_ms_b32"])))
        for col, snr in enumerate(snrs):
            ax = axes[row][col]
            for mi, m in enumerate(methods):
                color = cmap(mi % 20)
                rs = [r for r in rows if r["method"] == m and r["snr_db"] == snr]
                if not rs:
                    continue
                r = rs[0]
                y = float(r[metric]) * (100 if metric == "accuracy" else 1)
                kind = r["kind"]
                neural = kind.startswith("classifier") or kind.startswith("delay")
                marker = {"classifier_spectral": "o", "classifier_resnet": "s", "delay_correlation": "D"}.get(kind, "^")
                if m.endswith("(refine off)"):
                    marker = "v"
                shipped = m.startswith("shipped")
                xs = [float(r["fps_cpu_b%d" % b]) for b in (1, 32, 256)]
                if neural:
                    ax.plot(xs, [y] * 3, "-", color=color, lw=0.6, alpha=0.5, zorder=1)
                    ax.scatter(xs, [y] * 3, s=[14, 40, 70], marker=marker, color=color,
                               edgecolors="k" if shipped else "none", zorder=3, label=m)
                else:
                    ax.scatter([xs[0]], [y], s=90, marker="*", color=color, edgecolors="k", zorder=3, label=m)
            ax.set_xscale("log")
            if metric != "accuracy":
                ax.set_yscale("log")
            ax.set_title("%s at %s dB" % (tname, snr))
            ax.set_xlabel("frames/s per CPU-second, 1 thread")
            ax.set_ylabel(ylabel)
            ax.grid(True, which="both", alpha=0.3)
            if col == 2:
                ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.suptitle("gr-sems decoders: speed against accuracy on the same fresh frames (apps/evaluation/sems_pareto.py)\n"
                 "networks: small/mid/large marker = batch 1/32/256, black edge = shipped bundle; stars: classical, per frame")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "pareto.png"), dpi=110)
    with open(os.path.join(args.out, "pareto.md"), "w") as f:
        f.write("\n".join(header(args) + md) + "\n")
    print("wrote %s/pareto.png and pareto.md" % args.out)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="docs/pareto")
    p.add_argument("--build", default="build")
    p.add_argument("--bundles", default="build/pareto_bundles", help="where the sweep's bundles go")
    p.add_argument("--phases", default="train,eval,plot")
    p.add_argument("--tasks", default="classify,delay")
    p.add_argument("--only", nargs="*", help="train only these sweep points")
    p.add_argument("--frames", type=int, default=3000, help="test frames per SNR")
    p.add_argument("--speed-frames", type=int, default=2048)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--fast", nargs="*", default=["models/classifier_fast", "models/delay_single_fast"],
                   help="fast bundles to add as points")
    args = p.parse_args()
    os.makedirs(os.path.join(args.out, "logs"), exist_ok=True)
    os.makedirs(args.bundles, exist_ok=True)
    phases, tasks = args.phases.split(","), args.tasks.split(",")
    both = [("classify", CLASSIFY, CLASSIFY_SWEEP, "models/classifier", []),
            ("delay", DELAY, DELAY_SWEEP, "models/delay_single", ["--no-refine"])]
    if "train" in phases:
        for tname, task, sweep, _, _ in both:
            if tname in tasks:
                train(args, task, sweep)
    if "eval" in phases:
        for tname, task, sweep, shipped, extra in both:
            if tname in tasks:
                evaluate(args, tname, task, sweep, shipped, extra)
    if "plot" in phases:
        plot(args)


if __name__ == "__main__":
    main()
