#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: what each impairment of an SDR front end costs the shipped bundles.

Streams frames through the time-domain chain with the radio front end in between, and scores
the classifier sink (accuracy) and the delay-estimator sink (single-path MAE in delay index):

    pilot_mapper -> ofdm_tx -+-> radio_front_end (leakage, oscillators, IQ, DC, converter)
                             |     -> [unknown start: delay] -> [skiphead: the start found] -+
                             +-----------------------------------------------------------------+-> leakage_canceller
                                 -> ofdm_rx -> pilot_extractor -> classifier / delay sink

One impairment at a time, every other one off, at 10 and 20 dB SNR per resource element,
frame start known (the impairment's own cost); then the combined monostatic radio
(examples/radios/sdr_monostatic.json: leakage 40 dB over the echo, shared oscillator
-90 dBc/Hz at 100 kHz, IQ 0.5 dB / 3 deg, DC, 12-bit converter at 4x rms) with an unknown
frame start found by frame_sync, next to the ideal radio with a known start (the reference);
then the same with the bundles trained for that radio (sems_train --radio), on it and on the
ideal radio.
An unknown start is found by frame_sync once, in a short calibration run of the same radio (8
frames on the delay bundle's mask), and the scored runs skip that many samples (skiphead); the
leakage_canceller, fed with the transmitted samples, is the same in every row that has it; rows
say which stages ran.

Writes <out>/radio_sweep.csv; --table prints the Markdown table of a CSV, --plot draws it.

Usage:
    PYTHONPATH=build/python_pkg /usr/bin/python3 apps/evaluation/sems_radio_sweep.py --out DIR [--frames 400]
    /usr/bin/python3 apps/evaluation/sems_radio_sweep.py --table DIR/radio_sweep.csv
    /usr/bin/python3 apps/evaluation/sems_radio_sweep.py --plot DIR/radio_sweep.csv docs/results/radio_sweep.png
"""
import argparse
import csv
import json
import math
import os
import statistics
import sys
import time

FIELDS = ["sweep", "value", "snr_db", "task", "bundle", "receiver", "seed", "frames", "scored", "metric",
          "sync_offset", "sync_failures", "seconds"]

# One impairment at a time: (sweep name, axis label, keyword of front_end_settings, values).
SWEEPS = [
    ("leakage", "leakage over the echo (dB)", "leakage_db", [0.0, 20.0, 40.0, 60.0]),
    ("phase_noise", "phase noise at 100 kHz (dBc/Hz), shared oscillator", "phase_noise_dbc_hz",
     [-110.0, -90.0, -80.0, -70.0]),
    ("iq_gain", "IQ gain imbalance (dB)", "iq_gain_db", [0.5, 1.0, 3.0]),
    ("iq_phase", "IQ phase imbalance (deg)", "iq_phase_deg", [1.0, 3.0, 10.0]),
    ("enob", "converter resolution (bits, full scale 4x rms)", "adc_enob", [4.0, 6.0, 8.0, 10.0, 12.0, 14.0]),
    ("cfo", "carrier offset, separate oscillators (Hz)", "cfo_hz", [10.0, 100.0, 1000.0]),
]
QUICK_SWEEPS = [("leakage", "leakage over the echo (dB)", "leakage_db", [40.0])]
OFFSETS = [0, 777, 5000]  # unknown frame start: samples before the first frame


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def bundle_info(name):
    from gnuradio import sems
    return sems.model_bundle.load(sems.model_bundle.find(name))


def run_chain(bundle, snr_db, frames, seed, radio="", settings=None, offset=0, sync=False, cancel=False, cp=48,
              skip=0, forgetting=0.9, clip=True):
    """Streams `frames` + 1 frames; returns (metric, scored: the frames the sink scored, sync
    offset, sync failures).
    offset: samples of the radio's latency before the first frame; sync: frame_sync finds
    it; skip: samples dropped instead (a latency calibrated beforehand)."""
    import numpy as np
    from gnuradio import blocks, gr, sems
    b = bundle
    fr = b.frame
    n, m = fr.n_symbols, fr.n_subcarriers
    guards = list(fr.guard_subcarriers)
    mask_file = os.path.join(b.directory, b.mask_name)
    n_pilots = b.n_pilots
    classify = b.task == sems.task_kind.classify
    rng = np.random.default_rng(seed)
    n_data = (frames + 1) * (n * (m - len(guards)) - n_pilots)
    qpsk = ((rng.integers(0, 2, n_data) * 2 - 1) + 1j * (rng.integers(0, 2, n_data) * 2 - 1)) / math.sqrt(2)
    tb = gr.top_block()
    src = blocks.vector_source_c(qpsk.astype(np.complex64).tolist())
    mapper = sems.pilot_mapper(mask_file=mask_file, n_symbols=n, n_subcarriers=m, guard_subcarriers=guards)
    head = blocks.head(gr.sizeof_gr_complex * m, (frames + 1) * n)
    tx = sems.ofdm_tx(n_subcarriers=m, cp_len=cp)
    scene = json.dumps(json.loads(b.training_json)["scene"])
    lib = b.library.name() if b.library else "paper"
    fe = sems.radio_front_end(radio=radio, scene=scene, snr_db=snr_db, seed=seed, n_symbols=n, n_subcarriers=m,
                              bandwidth_hz=fr.bandwidth_hz, carrier_hz=fr.carrier_hz,
                              symbol_interval_s=fr.symbol_interval_s, cp_len=cp, class_library=lib,
                              tx_power=(m - len(guards)) / m, **(settings or {}))
    tb.connect(src, mapper, head, tx, fe)
    rx = fe
    if offset:
        late = blocks.delay(gr.sizeof_gr_complex, offset)  # the radio's unknown latency
        tb.connect(rx, late)
        rx = late
    if skip:
        drop = blocks.skiphead(gr.sizeof_gr_complex, skip)
        tb.connect(rx, drop)
        rx = drop
    fsync = None
    if sync:
        fsync = sems.frame_sync(mask_file=mask_file, n_symbols=n, n_subcarriers=m, cp_len=cp)
        tb.connect(rx, fsync)
        rx = fsync
    if cancel:
        frame_len = n * (m + cp)
        full_scale = fe.full_scale() if clip else 0.0  # 0.0 for an ideal converter: nothing clips
        canc = sems.leakage_canceller(window=frame_len, forgetting=forgetting, clip_level=full_scale)
        ref = blocks.copy(gr.sizeof_gr_complex)  # the transmitted samples, held while frame_sync searches
        ref.set_min_output_buffer(8 * frame_len)
        tb.connect(rx, (canc, 0))
        tb.connect(tx, ref, (canc, 1))
        rx = canc
    ofdm_rx = sems.ofdm_rx(n_subcarriers=m, cp_len=cp)
    ext = sems.pilot_extractor(mask_file=mask_file, n_symbols=n, n_subcarriers=m)
    if classify:
        sink = sems.classifier_sink(b.directory, n_pilots, 32, 1, 0, n, m)
    else:
        sink = sems.delay_estimator_sink(b.directory, n_pilots, 32, 1, 0, n, m)
    tb.connect(rx, ofdm_rx, ext, sink)
    tb.run()
    metric = sink.accuracy() if classify else sink.mae_index()
    return (metric, sink.frames_scored(), fsync.offset() if fsync else "", fsync.failures() if fsync else "")


def measure(args):
    os.makedirs(args.out, exist_ok=True)
    bundles = {"classify": bundle_info(args.classifier), "delay": bundle_info(args.delay)}
    # Bundles trained for the radio (sems_train --radio): the combined rows again with them.
    trained = {task: bundle_info(name) for task, name in (("classify", args.radio_classifier),
                                                         ("delay", args.radio_delay)) if name}
    rows = []
    path = os.path.join(args.out, "radio_sweep.csv")
    sweeps = QUICK_SWEEPS if args.quick else SWEEPS
    snrs = [20.0] if args.quick else [10.0, 20.0]
    offsets = OFFSETS[:2] if args.quick else OFFSETS
    seeds = [args.seed + k for k in range(args.seeds)]

    def point(sweep, value, snr, task, receiver, seed, use=None, **kw):
        t0 = time.time()
        b = (use or bundles)[task]
        metric, scored, off, fails = run_chain(b, snr, args.frames, seed, **kw)
        rows.append(dict(sweep=sweep, value=value, snr_db=snr, task=task, bundle=os.path.basename(b.directory),
                         receiver=receiver, seed=seed, frames=args.frames, scored=scored, metric=metric,
                         sync_offset=off, sync_failures=fails, seconds=round(time.time() - t0, 1)))
        log(f"  seed {seed}: {sweep} {value} @ {snr:g} dB, {task} [{receiver}]: {metric:.4f} ({scored} frames, "
            f"{time.time() - t0:.1f} s)")

    def found_offset(snr, seed, offset, settings=None):
        # The radio's latency (offset samples before the first frame) is found by frame_sync on
        # the delay mask's pilots through the same radio, as sems_sdr_calibrate does once per
        # radio, then dropped before the canceller (the classifier's one-subcarrier pilots
        # cannot time a frame themselves).
        return run_chain(bundles["delay"], snr, 8, seed, radio=args.radio, offset=offset, settings=settings,
                         sync=True)[2]

    per_seed = len(snrs) * (2 * (5 + len(offsets) + sum(len(v) for _, _, _, v in sweeps)) + 2 * len(trained))
    log(f"sems_radio_sweep: {per_seed * len(seeds)} points of {args.frames} frames ({len(seeds)} seeds)")
    for seed in seeds:
        for snr in snrs:
            for task in ("classify", "delay"):
                point("ideal", "", snr, task, "known start", seed)
                for sweep, _, key, values in sweeps:
                    for v in values:
                        extra = {"oscillator": "separate"} if key == "cfo_hz" else {}  # a CFO needs two oscillators
                        point(sweep, v, snr, task, "known start, canceller", seed, settings={key: v, **extra},
                              cancel=True)
                for off in offsets:
                    found = found_offset(snr, seed, off)
                    point("combined", off, snr, task, "frame_sync start, canceller", seed, radio=args.radio,
                          offset=off, skip=found, cancel=True)
                    rows[-1]["sync_offset"] = found  # what frame_sync found (the true latency is `value`)
                last = offsets[-1]
                found = found_offset(snr, seed, last)
                # What the canceller's handling of clipped samples is worth on this radio.
                point("combined_clipping_not_handled", last, snr, task, "frame_sync start, canceller", seed,
                      radio=args.radio, offset=last, skip=found, cancel=True, clip=False)
                # What the oscillator's phase noise on the leakage costs: the same radio without it.
                point("combined_without_phase_noise", last, snr, task, "frame_sync start, canceller", seed,
                      radio=args.radio, settings={"phase_noise_dbc_hz": None}, offset=last,
                      skip=found_offset(snr, seed, last, {"phase_noise_dbc_hz": None}), cancel=True)
                point("combined_no_canceller", 0, snr, task, "known start", seed, radio=args.radio)
                if task in trained:
                    # The bundles trained for this radio: on it, and on the ideal radio.
                    point("combined_radio_trained", last, snr, task, "frame_sync start, canceller", seed,
                          use=trained, radio=args.radio, offset=last, skip=found, cancel=True)
                    point("ideal_radio_trained", "", snr, task, "known start", seed, use=trained)
                # The same radio with a converter of more headroom: full scale at 8x the rms.
                eight = {"adc_full_scale_rms": 8.0}
                point("combined_full_scale_8x", last, snr, task, "frame_sync start, canceller", seed,
                      radio=args.radio, settings=eight, offset=last, skip=found_offset(snr, seed, last, eight),
                      cancel=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    log(f"sems_radio_sweep: {len(rows)} rows in {path}")


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def mean_over_seeds(rows):
    """One row per point: the metric's mean over the seeds, and its spread (sample standard
    deviation over seeds; 0 with one seed) in `spread`."""
    groups = {}
    for r in rows:
        groups.setdefault((r["sweep"], r["value"], r["receiver"], r["task"], r["snr_db"]), []).append(r)
    out = []
    for group in groups.values():
        values = [float(r["metric"]) for r in group]
        spread = statistics.stdev(values) if len(values) > 1 else 0.0
        out.append(dict(group[0], metric=statistics.fmean(values), spread=spread, seeds=len(values)))
    return out


def table(path):
    rows = mean_over_seeds(read(path))
    out = ["<!-- generated by apps/evaluation/sems_radio_sweep.py --table from its radio_sweep.csv: do not edit -->", ""]
    tasks = [("classify", "classifier accuracy", "{:.3f}"), ("delay", "delay MAE (index)", "{:.4f}")]
    snrs = sorted({float(r["snr_db"]) for r in rows})
    head = "| impairment | value | receiver | " + " | ".join(
        f"{label} @ {s:g} dB" for _, label, _ in tasks for s in snrs) + " |"
    out += [head, "|---" * (3 + len(tasks) * len(snrs)) + "|"]
    keys = []
    for r in rows:
        k = (r["sweep"], r["value"], r["receiver"])
        if k not in keys:
            keys.append(k)
    ideal = {(r["task"], float(r["snr_db"])): float(r["metric"]) for r in rows if r["sweep"] == "ideal"}
    for sweep, value, receiver in keys:
        cells = []
        for task, _, fmt in tasks:
            for s in snrs:
                r = next((r for r in rows if (r["sweep"], r["value"], r["receiver"], r["task"], float(r["snr_db"]))
                          == (sweep, value, receiver, task, s)), None)
                if r is None:
                    cells.append("")
                    continue
                v = float(r["metric"])
                ref = ideal.get((task, s))
                rel = ""
                if ref and sweep != "ideal":
                    rel = f" ({v - ref:+.3f})" if task == "classify" else f" ({v / ref:.2f}×)"
                spread = f" ± {fmt.format(r['spread'])}" if r["seeds"] > 1 else ""
                cells.append(fmt.format(v) + spread + rel)
        out.append(f"| {sweep.replace('_', ' ')} | {value} | {receiver} | " + " | ".join(cells) + " |")
    seeds = max(r["seeds"] for r in rows)
    # The frames each run scored (run_chain streams --frames + 1 frames).
    scored = sorted({int(r["scored"]) for r in read(path)})
    frames = str(scored[0]) if len(scored) == 1 else f"{scored[0]} to {scored[-1]}"
    out += ["", f"Each cell: the mean over {seeds} seeds of {frames} scored frames each"
            + (", ± the standard deviation over the seeds" if seeds > 1 else "")
            + ". In brackets: the classifier's accuracy minus the ideal radio's, the delay MAE as a multiple "
            "of the ideal radio's (same SNR, same frames).", ""]
    print("\n".join(out))


def plot(path, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = mean_over_seeds(read(path))
    fig, axes = plt.subplots(2, len(SWEEPS), figsize=(3.2 * len(SWEEPS), 6.2), squeeze=False)
    ideal = {(r["task"], float(r["snr_db"])): float(r["metric"]) for r in rows if r["sweep"] == "ideal"}
    for col, (sweep, label, _, _) in enumerate(SWEEPS):
        for row, (task, ylabel) in enumerate((("classify", "classifier accuracy"), ("delay", "delay MAE (index)"))):
            ax = axes[row][col]
            for snr, colour in ((10.0, "tab:blue"), (20.0, "tab:red")):
                pts = sorted((float(r["value"]), float(r["metric"]), float(r["spread"])) for r in rows
                             if r["sweep"] == sweep and r["task"] == task and float(r["snr_db"]) == snr)
                if pts:
                    x, y, e = zip(*pts)  # the bars: the standard deviation over the seeds
                    ax.errorbar(x, y, yerr=e, fmt="o-", color=colour, capsize=3, label=f"{snr:g} dB")
                if (task, snr) in ideal:
                    ax.axhline(ideal[(task, snr)], color=colour, ls="--", lw=0.8)
            if row == 0:  # one scale for every panel: a point of accuracy looks the same everywhere
                ax.set_ylim(0.96, 1.002)
            if row == 1:
                ax.set_xlabel(label, fontsize=8)
                ax.set_yscale("log")
            if col == 0:
                ax.set_ylabel(ylabel)
            ax.tick_params(labelsize=7)
            if row == 0 and col == 0:
                ax.legend(fontsize=7, title="SNR (dashed: ideal radio;\nbars: spread over seeds)", title_fontsize=7)
    fig.suptitle("Shipped bundles through an SDR front end, one impairment at a time (leakage canceller on)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument("--out", help="directory for radio_sweep.csv")
    p.add_argument("--frames", type=int, default=400, help="frames per point (default 400)")
    p.add_argument("--seed", type=int, default=7, help="seed of the data, the scene and the radio (the first)")
    p.add_argument("--seeds", type=int, default=1, help="seeds per point: seed, seed + 1, ... (default 1)")
    p.add_argument("--classifier", default="classifier", help="classifier bundle (name or folder)")
    p.add_argument("--delay", default="delay_single", help="delay bundle (name or folder)")
    p.add_argument("--radio-classifier", default="classifier_monostatic",
                   help="classifier bundle trained for the radio (sems_train --radio), scored in the combined "
                   "and ideal rows too; \"\" for none")
    p.add_argument("--radio-delay", default="",
                   help="delay bundle trained for the radio (default none: see docs/results/notes/shipped_models.md)")
    p.add_argument("--radio", default="", help="radio file of the combined rows "
                   "(default: examples/radios/sdr_monostatic.json of the source tree)")
    p.add_argument("--quick", action="store_true", help="one point per part (checks the tool runs)")
    p.add_argument("--table", metavar="CSV", help="print the Markdown table of a radio_sweep.csv")
    p.add_argument("--plot", nargs=2, metavar=("CSV", "PNG"), help="draw the figure of a radio_sweep.csv")
    args = p.parse_args()
    if args.table:
        table(args.table)
    elif args.plot:
        plot(*args.plot)
    else:
        if not args.out:
            p.error("give --out (or --table / --plot)")
        if args.frames < 1:
            p.error("--frames must be >= 1")
        if args.seeds < 1:
            p.error("--seeds must be >= 1")
        if not args.radio:
            here = os.path.dirname(os.path.abspath(__file__))
            src = os.environ.get("SEMS_SOURCE_DIR", os.path.join(here, "..", ".."))
            args.radio = os.path.join(src, "examples", "radios", "sdr_monostatic.json")
        if not os.path.isfile(args.radio):
            p.error(f"--radio {args.radio}: no such file")
        measure(args)


if __name__ == "__main__":
    main()
