#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: what the cyclic prefix does to the shipped models through the time-domain chain.

    FD: qpsk -> pilot_mapper -> target_channel -> pilot_extractor -> sink
    TD: qpsk -> pilot_mapper -> ofdm_tx(CP) -> target_channel_td(CP) -> ofdm_rx(CP) -> pilot_extractor -> sink

with the bundles' own training scenes (the class table: 0-200 m), the same seed for every
row, one LibTorch thread. Prints one line per (SNR, bundle, chain): accuracy or delay MAE.

Usage:
    PYTHONPATH=build/python_pkg /usr/bin/python3 apps/evaluation/sems_td_cp_accuracy.py [--frames 1000] [--snr 10 30] [--cp 16 32 48]
"""
import argparse
import json
import os

from gnuradio import analog, blocks, digital, gr, sems

QPSK = [(1 + 1j) / 2 ** 0.5, (-1 + 1j) / 2 ** 0.5, (-1 - 1j) / 2 ** 0.5, (1 - 1j) / 2 ** 0.5]


def run(bundle_dir, task, cp, frames, snr, seed):
    """cp None: the frequency-domain chain."""
    scene = json.dumps(json.load(open(os.path.join(bundle_dir, "bundle.json")))["training"]["scene"])
    mask = os.path.join(bundle_dir, "mask.json")
    fs = sems.frame_settings()
    tb = gr.top_block()
    bits = analog.random_uniform_source_b(0, 4, seed)
    qpsk = digital.chunks_to_symbols_bc(QPSK, 1)
    mapper = sems.pilot_mapper(mask_file=mask)
    head = blocks.head(gr.sizeof_gr_complex * fs.n_subcarriers, frames * fs.n_symbols)
    ext = sems.pilot_extractor(mask_file=mask)
    make_sink = sems.classifier_sink if task == "classify" else sems.delay_estimator_sink
    sink = make_sink(bundle_dir=bundle_dir, n_pilots=32, batch_size=50, threads=1)
    if cp is None:
        tb.connect(bits, qpsk, mapper, head, sems.target_channel(scene=scene, snr_db=snr, seed=seed), ext, sink)
    else:
        ch = sems.target_channel_td(scene=scene, snr_db=snr, seed=seed, cp_len=cp)
        tb.connect(bits, qpsk, mapper, head, sems.ofdm_tx(fs.n_subcarriers, cp), ch,
                   sems.ofdm_rx(fs.n_subcarriers, cp), ext, sink)
    tb.run()
    return sink


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "models"))
    ap.add_argument("--frames", type=int, default=1000)
    ap.add_argument("--snr", type=float, nargs="+", default=[10.0, 30.0])
    ap.add_argument("--cp", type=int, nargs="+", default=[16, 32, 48])
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    print("| SNR (dB) | bundle | chain | frames | result |\n|---|---|---|---|---|")
    for snr in a.snr:
        for name, task in (("classifier", "classify"), ("delay_single", "delay")):
            for cp in [None] + a.cp:
                s = run(os.path.join(a.models, name), task, cp, a.frames, snr, a.seed)
                chain = "FD (target_channel)" if cp is None else f"TD, CP {cp}"
                res = (f"accuracy {100 * s.accuracy():.1f} %" if task == "classify"
                       else f"MAE {s.mae_index():.4f} index ({s.mae_m():.3f} m)")
                print(f"| {snr:g} | {name} | {chain} | {s.frames()} | {res} |", flush=True)


if __name__ == "__main__":
    main()
