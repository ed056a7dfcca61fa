#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: pilot_mapper, the learned-pilot OFDM transmitter (docs/design.md §2):
X = sqrt(E_p)·s_p at the pilots, sqrt(E_d)·data elsewhere, N symbols per frame."""
import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

N, M = 4, 8
POS = [31, 0, 9, 3, 17]  # any order: the mask sorts them
SP = 0.6 - 0.8j
EP, ED = 2.5, 0.5


def mapper(**kw):
    args = dict(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP, pilot_power=EP, data_power=ED)
    args.update(kw)
    return sems.pilot_mapper(**args)


def expected(data, pos=POS, ep=EP, ed=ED):
    """The frames the mapper must build from `data`, row-major."""
    pilots = np.zeros(N * M, dtype=bool)
    pilots[pos] = True
    per_frame = N * M - len(pos)
    frames = len(data) // per_frame if per_frame else 0
    out = np.empty((frames, N * M), dtype=np.complex64)
    for f in range(frames):
        out[f, pilots] = math.sqrt(ep) * np.complex64(SP)
        out[f, ~pilots] = math.sqrt(ed) * data[f * per_frame:(f + 1) * per_frame]
    return out.reshape(-1, M)


def data_symbols(count, seed=1):
    rng = np.random.default_rng(seed)
    return (rng.standard_normal(count) + 1j * rng.standard_normal(count)).astype(np.complex64)


def run(block, data, chunk=None, tags=()):
    src = blocks.vector_source_c(data.tolist(), tags=list(tags))
    sink = blocks.vector_sink_c(M)
    if chunk:
        src.set_max_noutput_items(chunk)
        block.set_max_noutput_items(chunk)
    tb = gr.top_block()
    tb.connect(src, block, sink)
    tb.run()
    return np.array(sink.data(), dtype=np.complex64).reshape(-1, M), sink.tags()


def tag_list(tags, key):
    return [(t.offset, pmt.to_python(t.value)) for t in tags if pmt.symbol_to_string(t.key) == key]


class qa_pilot_mapper(gr_unittest.TestCase):

    def test_001_frames_and_tags(self):
        frames = 4
        data = data_symbols(frames * (N * M - len(POS)) + 3)  # 3 left over: not a whole frame's worth
        for chunk in (None, 1, 2, 7):
            with self.subTest(chunk=chunk):
                b = mapper()
                x, tags = run(b, data, chunk)
                np.testing.assert_allclose(x, expected(data), rtol=1e-6)
                self.assertEqual(tag_list(tags, sems.keys.frame_tag), [(f * N, f) for f in range(frames)])
                self.assertEqual((b.frames(), b.n_pilots(), b.data_per_frame()), (frames, 5, N * M - 5))

    def test_002_data_tags_follow_their_symbol(self):
        per_frame = N * M - len(POS)
        data = data_symbols(2 * per_frame)
        key = pmt.intern("user")
        # data symbol j lands in the OFDM symbol of its (frame, row)
        picks = [0, 6, 7, per_frame - 1, per_frame + 8]
        tags = [gr.tag_utils.python_to_tag((j, key, pmt.from_long(j))) for j in picks]
        pilots = np.zeros(N * M, dtype=bool)
        pilots[POS] = True
        data_cells = np.flatnonzero(~pilots)
        want = [((j // per_frame) * N + data_cells[j % per_frame] // M, j) for j in picks]
        _, out_tags = run(mapper(), data, tags=tags)
        self.assertEqual(tag_list(out_tags, "user"), want)

    def test_003_pilots_only_is_a_source(self):
        # N_p = N·M: no data, the input stays unconnected, frames come as fast as asked.
        b = mapper(pilot_positions=list(range(N * M)))
        self.assertEqual(b.data_per_frame(), 0)
        head = blocks.head(gr.sizeof_gr_complex * M, 3 * N)
        sink = blocks.vector_sink_c(M)
        tb = gr.top_block()
        tb.connect(b, head, sink)
        tb.run()
        x = np.array(sink.data()).reshape(-1, M)
        np.testing.assert_allclose(x, np.full((3 * N, M), math.sqrt(EP) * np.complex64(SP)), rtol=1e-6)
        self.assertEqual(tag_list(sink.tags(), sems.keys.frame_tag), [(0, 0), (N, 1), (2 * N, 2)])

    def test_004_data_input_required_otherwise(self):
        tb = gr.top_block()
        tb.connect(mapper(), blocks.head(gr.sizeof_gr_complex * M, N), blocks.null_sink(gr.sizeof_gr_complex * M))
        with self.assertRaises(Exception) as cm:
            tb.run()
        self.assertIn("data input must be connected", str(cm.exception))

    def test_005_one_pilot(self):
        data = data_symbols(2 * (N * M - 1))
        x, _ = run(mapper(pilot_positions=[13]), data)
        np.testing.assert_allclose(x, expected(data, pos=[13]), rtol=1e-6)

    def test_006_power_setters(self):
        b = mapper()
        b.set_pilot_power(4.0)
        b.set_data_power(0.0)  # pilots only on the air
        self.assertEqual((b.pilot_power(), b.data_power()), (4.0, 0.0))
        data = data_symbols(N * M - len(POS))
        x, _ = run(b, data)
        np.testing.assert_allclose(x, expected(data, ep=4.0, ed=0.0), rtol=1e-6)
        for bad in (-1.0, math.nan, math.inf):
            for setter in (b.set_pilot_power, b.set_data_power):
                with self.assertRaises(ValueError) as cm:
                    setter(bad)
                self.assertIn("must be finite and >= 0", str(cm.exception))
        self.assertEqual(b.pilot_power(), 4.0)

    def test_007_amplitude_extremes(self):
        data = data_symbols(N * M - len(POS))
        for amp in (1e-20, 1e20):
            with self.subTest(amplitude=amp):
                x, _ = run(mapper(pilot_power=amp * amp, data_power=1.0), data * np.float32(amp))
                self.assertTrue(np.all(np.isfinite(x)))
                np.testing.assert_allclose(x / amp, expected(data, ep=1.0, ed=1.0), rtol=1e-5)

    def test_008_mask_file(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "mask.json")
            sems.pilot_mask(N, M, [(p // M, p % M) for p in POS], SP).save(path)
            b = mapper(pilot_positions=[], mask_file=path)
            self.assertEqual(b.mask().flat_indices(), sorted(POS))
            data = data_symbols(N * M - len(POS))
            x, _ = run(b, data)
            np.testing.assert_allclose(x, expected(data), rtol=1e-6)
            with self.assertRaises(ValueError) as cm:
                mapper(pilot_positions=[], mask_file=path, pilot_symbol=1)
            self.assertIn("differs from the pilot_symbol", str(cm.exception))
            with self.assertRaises(ValueError) as cm:
                mapper(pilot_positions=[], mask_file=path, n_subcarriers=2 * M)
            self.assertIn("the pilot mask is 4 x 8 but the frame is 4 x 16", str(cm.exception))
            with open(path, "w") as f:
                f.write('{"format": "sems.pilot_mask", "version": 1, "n_symbols": 4, "n_subcarriers": 8,'
                        ' "pilot_symbol": [1, 0], "pilots": [[0, 1], [0, 1]]}')
            with self.assertRaises(ValueError) as cm:
                mapper(pilot_positions=[], mask_file=path, pilot_symbol=1)
            self.assertIn("duplicate", str(cm.exception))
            self.assertIn("mask.json", str(cm.exception))

    def test_009_bad_parameters_refused(self):
        def refuses(text, **kw):
            with self.assertRaises(ValueError) as cm:
                mapper(**kw)
            self.assertIn(text, str(cm.exception))
            self.assertIn("pilot_mapper", str(cm.exception))

        refuses("duplicate position [0, 3]", pilot_positions=[3, 9, 3])
        refuses("pilot_positions[1] = 32 is outside the 4 x 8 grid", pilot_positions=[0, 32])
        refuses("outside", pilot_positions=[-5])
        refuses("no pilots", pilot_positions=[])
        refuses("must be >= 1", n_symbols=0)
        refuses("pilot_power must be finite and >= 0", pilot_power=-1.0)
        refuses("pilot_power must be finite and >= 0", pilot_power=math.nan)
        refuses("data_power must be finite and >= 0", data_power=math.inf)
        refuses("pilot_symbol", pilot_symbol=0)


    def test_010_guard_subcarriers_carry_nothing(self):
        guards = [5, 2]  # any order
        frames = 3
        per_frame = N * (M - 2) - len(POS)
        data = data_symbols(frames * per_frame)
        b = mapper(guard_subcarriers=guards)
        self.assertEqual(b.data_per_frame(), per_frame)
        x, _ = run(b, data)
        self.assertEqual(x.shape, (frames * N, M))
        self.assertTrue(np.all(x[:, guards] == 0))
        # Pilots where the mask puts them; data row-major over the other non-guard cells.
        pilots = np.zeros(N * M, dtype=bool)
        pilots[POS] = True
        used = ~pilots & ~np.isin(np.arange(N * M) % M, guards)
        grid = x.reshape(frames, N * M)
        for f in range(frames):
            np.testing.assert_allclose(grid[f, pilots], math.sqrt(EP) * np.complex64(SP), rtol=1e-6)
            np.testing.assert_allclose(grid[f, used], math.sqrt(ED) * data[f * per_frame:(f + 1) * per_frame],
                                       rtol=1e-6)
        # No guards: the frame is as before (every cell carries a pilot or data).
        self.assertEqual(mapper().data_per_frame(), N * M - len(POS))

    def test_011_bad_guards_refused(self):
        def refuses(text, **kw):
            with self.assertRaises(ValueError) as cm:
                mapper(**kw)
            self.assertIn(text, str(cm.exception))

        refuses("pilot 4 at [3, 7] is on guard subcarrier 7", guard_subcarriers=[7])
        refuses("subcarrier 8 is outside", guard_subcarriers=[8])
        refuses("subcarrier 2 is listed twice", guard_subcarriers=[2, 2])


if __name__ == "__main__":
    gr_unittest.run(qa_pilot_mapper)
