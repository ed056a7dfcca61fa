#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: range_doppler_map. A single target with the grid model's phasors
(steering.h: exp(-j2π m k/M)·exp(j2π b n/N)) peaks at row b + N/2, column k; on a full
grid with a unit amplitude the peak reads 0 dB; tags follow their frame; a NaN frame is
skipped and counted; bad parameters are rejected."""
import json
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

N, M = 16, 32


def target_grid(delay_index, doppler_bin, amplitude=1.0):
    n = np.arange(N)[:, None]
    m = np.arange(M)[None, :]
    return (amplitude * np.exp(-2j * np.pi * m * delay_index / M)
            * np.exp(2j * np.pi * doppler_bin * n / N)).astype(np.complex64)


def run(frames, positions, window="hann"):
    np_ = len(positions)
    src = blocks.vector_source_c(np.concatenate(frames).ravel(), False, np_)
    rdm = sems.range_doppler_map(pilot_positions=positions, n_symbols=N, n_subcarriers=M, window=window)
    snk = blocks.vector_sink_f(N * M)
    tb = gr.top_block()
    tb.connect(src, rdm, snk)
    tb.run()
    return rdm, np.array(snk.data()).reshape(-1, N, M)


class qa_range_doppler_map(gr_unittest.TestCase):

    def test_full_grid_peak_cell_and_level(self):
        full = list(range(N * M))
        cases = [(5, 3), (0, 0), (31, -8), (12, 7)]
        frames = [target_grid(k, b).ravel() for k, b in cases]
        for window in ("hann", "rect"):
            rdm, maps = run(frames, full, window)
            self.assertEqual(rdm.frames_out(), len(cases))
            for (k, b), mp in zip(cases, maps):
                row, col = np.unravel_index(np.argmax(mp), mp.shape)
                self.assertEqual((row, col), ((b + N // 2) % N, k % M), f"{window} k={k} b={b}")
                self.assertAlmostEqual(mp[row, col], 0.0, places=3)
            if window == "rect":  # on-bin, rectangular: every other cell is empty
                mp = maps[0].copy()
                mp[(3 + N // 2) % N, 5] = -300.0
                self.assertLess(mp.max(), -100.0)

    def test_sparse_pilots_peak_cell(self):
        rng = np.random.default_rng(3)
        positions = sorted(rng.choice(N * M, size=N * M // 4, replace=False).tolist())
        k, b = 9, -5
        grid = target_grid(k, b).ravel()[positions]
        _, maps = run([grid], positions)
        row, col = np.unravel_index(np.argmax(maps[0]), maps[0].shape)
        self.assertEqual((row, col), ((b + N // 2) % N, k))

    def test_nonfinite_frame_skipped_and_tags_follow(self):
        full = list(range(N * M))
        good1, bad, good2 = target_grid(2, 1).ravel(), target_grid(4, 2).ravel(), target_grid(6, 3).ravel()
        bad[7] = np.nan
        tags = [gr.tag_utils.python_to_tag((i, pmt.intern("sems_frame"), pmt.from_uint64(10 + i),
                                            pmt.intern("src"))) for i in range(3)]
        src = blocks.vector_source_c(np.concatenate([good1, bad, good2]), False, N * M, tags)
        rdm = sems.range_doppler_map(pilot_positions=full, n_symbols=N, n_subcarriers=M)
        snk = blocks.vector_sink_f(N * M)
        tb = gr.top_block()
        tb.connect(src, rdm, snk)
        tb.run()
        maps = np.array(snk.data()).reshape(-1, N, M)
        self.assertEqual(len(maps), 2)
        self.assertEqual(rdm.frames_skipped_nonfinite(), 1)
        cells = [np.unravel_index(np.argmax(mp), mp.shape) for mp in maps]
        self.assertEqual(cells, [(1 + N // 2, 2), (3 + N // 2, 6)])
        got = sorted((t.offset, pmt.to_uint64(t.value)) for t in snk.tags()
                     if pmt.symbol_to_string(t.key) == "sems_frame")
        self.assertEqual(got, [(0, 10), (1, 12)])

    def test_mask_file_with_any_pilot_symbol(self):
        # The map reads the extractor's pilots, already divided by the pilot symbol: the
        # extractor's mask file is taken whatever its pilot_symbol, and maps as its positions do.
        rng = np.random.default_rng(5)
        positions = sorted(rng.choice(N * M, size=N * M // 4, replace=False).tolist())
        mask = {"format": "sems.pilot_mask", "version": 1, "n_symbols": N, "n_subcarriers": M,
                "n_pilots": len(positions), "pilot_symbol": [0.0, 1.0],
                "pilots": [[p // M, p % M] for p in positions]}
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "mask.json")
            with open(path, "w") as f:
                json.dump(mask, f)
            rdm = sems.range_doppler_map(mask_file=path, n_symbols=N, n_subcarriers=M)
        self.assertEqual(rdm.n_pilots(), len(positions))
        grid = target_grid(9, -5).ravel()[positions]
        src = blocks.vector_source_c(grid, False, len(positions))
        snk = blocks.vector_sink_f(N * M)
        tb = gr.top_block()
        tb.connect(src, rdm, snk)
        tb.run()
        _, by_positions = run([grid], positions)
        np.testing.assert_array_equal(np.array(snk.data()).reshape(-1, N, M), by_positions)

    def test_bad_parameters_rejected(self):
        with self.assertRaisesRegex(ValueError, "window"):
            sems.range_doppler_map(pilot_positions=[0, 1], n_symbols=N, n_subcarriers=M, window="kaiser")
        with self.assertRaisesRegex(ValueError, "n_symbols"):
            sems.range_doppler_map(pilot_positions=[0], n_symbols=0, n_subcarriers=M)
        with self.assertRaises(ValueError):
            sems.range_doppler_map(pilot_positions=[N * M], n_symbols=N, n_subcarriers=M)
        with self.assertRaises(ValueError):
            sems.range_doppler_map(mask_file="/nonexistent/mask.json", n_symbols=N, n_subcarriers=M)


if __name__ == "__main__":
    gr_unittest.run(qa_range_doppler_map)
