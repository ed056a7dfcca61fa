#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: throughput of the two target emulators and of gr-radar's point-target
simulator, in samples/s, in one run and one harness:

    vector_source(repeat) -> [stream_to_tagged_stream ->] block -> head -> null_sink,
    top_block.run(); rate per CPU second of the process (all its threads: on a shared
    machine the wall clock measures the neighbours) and per wall second; best of --repeat
    runs, rows interleaved.

First row: blocks.multiply_const_cc, the anchor (the harness's own cost per sample).
Scenes: 1, 3 and 10 point targets (cars at 10 + 7.3 k m, 15 m/s, one path each, no
fading for gr-radar's sake), noise off; then noise on and micro-Doppler (drones) rows.
- target_channel_td: samples (M + CP per symbol) in and out.
- target_channel (frequency domain): symbols of M; counted as (M + CP) samples per symbol,
  the samples it stands for in the time-domain chain (its ofdm_tx/ofdm_rx cost not included).
- radar.static_target_simulator_cc: packets of one frame, N (M + CP) samples (its FFT length),
  same ranges, velocities, sample rate and carrier; random phase on, self-coupling off.

Usage:
    PYTHONPATH=build/python_pkg /usr/bin/python3 apps/benchmarks/sems_bench_td.py [--seconds 1] [--repeat 3] [--cp 16]
"""
import argparse
import json
import math
import time

import numpy as np
from gnuradio import blocks, gr, sems

try:
    from gnuradio import radar
except ImportError:  # gr-radar is optional: its rows are then skipped
    radar = None


def scene(n_targets, micro_doppler):
    targets = []
    for k in range(n_targets):
        t = {"class": "drone" if micro_doppler else "car", "range_m": 10.0 + 7.3 * k,
             "velocity_mps": 7.0 if micro_doppler else 15.0, "power": 1, "paths": [{"excess_range_m": 0, "power": 1}]}
        if micro_doppler:
            t["micro_doppler"] = {"rate_hz": 100.0, "amplitude_m": 0.01, "phase_rad": 0.3 * k}
        targets.append(t)
    return json.dumps({"format": "sems.scene", "version": 1, "fading": "none", "targets": targets})


def timed(data, vlen, make_block, n_items, packet_len=None):
    tb = gr.top_block()
    src = blocks.vector_source_c(data, True, vlen)
    blk = make_block()
    head = blocks.head(gr.sizeof_gr_complex * vlen, n_items)
    sink = blocks.null_sink(gr.sizeof_gr_complex * vlen)
    if packet_len:
        tagger = blocks.stream_to_tagged_stream(gr.sizeof_gr_complex, 1, packet_len, "packet_len")
        tb.connect(src, tagger, blk, head, sink)
    else:
        tb.connect(src, blk, head, sink)
    c0, t0 = time.process_time(), time.perf_counter()
    tb.run()
    return time.process_time() - c0, time.perf_counter() - t0


def items_per_second(data, vlen, make_block, seconds, packet_len=None):
    """(items per CPU second, items per wall second)"""
    n = 1 << 12
    t = timed(data, vlen, make_block, n, packet_len)[1]
    while t < 0.05:
        n *= 4
        t = timed(data, vlen, make_block, n, packet_len)[1]
    target = max(1, int(seconds * n / t))
    if packet_len:
        target = max(packet_len, target // packet_len * packet_len)
    cpu, wall = timed(data, vlen, make_block, target, packet_len)
    return target / cpu, target / wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=1.0, help="wall time per measurement (s)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per row, best reported")
    ap.add_argument("--cp", type=int, default=16, help="cyclic prefix (samples)")
    ap.add_argument("--snr", type=float, default=20.0, help="SNR of the noise-on rows (dB)")
    a = ap.parse_args()
    if not (a.seconds > 0) or a.repeat < 1 or a.cp < 0:
        ap.error("--seconds > 0, --repeat >= 1 and --cp >= 0 required")

    fs = sems.frame_settings()
    m, n, b, fc = fs.n_subcarriers, fs.n_symbols, fs.bandwidth_hz, fs.carrier_hz
    s = m + a.cp
    frame = n * s
    rng = np.random.default_rng(1)
    data = ((rng.standard_normal(4 * frame) + 1j * rng.standard_normal(4 * frame)) / math.sqrt(2)).astype(
        np.complex64).tolist()
    inf = float("inf")

    rows = []  # (group, label, vlen, make, samples per item, packet_len)
    # The harness itself, with the cheapest block there is: what every row pays before its model.
    rows.append(("anchor", "blocks.multiply_const_cc (harness anchor)", 1,
                 lambda: blocks.multiply_const_cc(0.5), 1, None))
    for k in (1, 3, 10):
        rows.append((k, f"target_channel_td  {k:2d} targets, noiseless",
                     1, lambda k=k: sems.target_channel_td(scene=scene(k, False), snr_db=inf, cp_len=a.cp), 1, None))
        rows.append((k, f"target_channel (FD) {k:2d} targets, noiseless",
                     m, lambda k=k: sems.target_channel(scene=scene(k, False), snr_db=inf), s, None))
        if radar is not None:
            rows.append((k, f"gr-radar static_target_simulator_cc {k:2d} targets",
                         1, lambda k=k: radar.static_target_simulator_cc(
                             [10.0 + 7.3 * i for i in range(k)], [15.0] * k, [1.0] * k, [0.0] * k, [0.0],
                             int(b), fc, -10.0, True, False, "packet_len"), 1, frame))
    for k in (1, 3, 10):
        rows.append((f"{k}n", f"target_channel_td  {k:2d} targets, SNR {a.snr:g} dB",
                     1, lambda k=k: sems.target_channel_td(scene=scene(k, False), snr_db=a.snr, cp_len=a.cp), 1, None))
        rows.append((f"{k}md", f"target_channel_td  {k:2d} drones (micro-Doppler), noiseless",
                     1, lambda k=k: sems.target_channel_td(scene=scene(k, True), snr_db=inf, cp_len=a.cp), 1, None))

    best = [0.0] * len(rows)
    best_wall = [0.0] * len(rows)
    for _ in range(a.repeat):
        for i, (_, _, vlen, make, per_item, plen) in enumerate(rows):
            src = data if vlen == 1 else data[: len(data) // vlen * vlen]
            cpu, wall = items_per_second(src, vlen, make, a.seconds, plen)
            best[i] = max(best[i], per_item * cpu)
            best_wall[i] = max(best_wall[i], per_item * wall)

    print(f"sems_bench_td: M = {m}, CP = {a.cp}, N = {n}, B = {b / 1e6:g} MHz; best of {a.repeat} runs of "
          f"{a.seconds:g} s per row;\nMsamples per CPU second of the process and per wall second (FD counted as M + CP "
          f"samples per symbol)")
    print(f"{'block':<58} {'MS/CPU-s':>9} {'MS/wall-s':>9} {'TD vs this (CPU)':>17}")
    td_of = {g: best[i] for i, (g, label, *_rest) in enumerate(rows) if label.startswith("target_channel_td ")}
    for i, (g, label, *_rest) in enumerate(rows):
        ratio = td_of.get(g, float("nan")) / best[i]
        print(f"{label:<58} {best[i] / 1e6:9.2f} {best_wall[i] / 1e6:9.2f} {ratio:16.2f}x")


if __name__ == "__main__":
    main()
