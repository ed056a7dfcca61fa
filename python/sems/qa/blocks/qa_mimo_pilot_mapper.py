#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: mimo_pilot_mapper. Each output carries its element's pilots (a_kj·sqrt(E_p)·s_p)
and every element the data at sqrt(E_d/N_t); through the emulator with a MIMO array and the
pilot extractor on the same file, the receive streams give exactly mimo_pilots(); frame tags on
every output; bad parameters refused by name."""
import json
import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

ARRAY = "mimo2x4_3g"  # 4 receive, 2 transmit elements
SEED = 3


def write(mask, folder, name="m.json"):
    path = os.path.join(folder, name)
    mask.save(path)
    return path


def scene_text(az):
    return json.dumps({"format": "sems.scene", "version": 1, "array": ARRAY,
                       "targets": [{"class": "car", "range_m": 70, "velocity_mps": 9, "azimuth_rad": az}]})


class qa_mimo_pilot_mapper(gr_unittest.TestCase):

    def setUp(self):
        self.fs = sems.frame_settings()
        self.n, self.m = self.fs.n_symbols, self.fs.n_subcarriers
        self.dir = tempfile.TemporaryDirectory()
        pilots = sems.pilot_mask.from_pattern("random", self.fs, 32, 7)
        self.tdm = sems.mimo_mask.time_division(pilots, 2)
        self.same = sems.mimo_mask.same_pilots(pilots, 2)

    def tearDown(self):
        self.dir.cleanup()

    def map_frames(self, mask, frames=2, pilot_power=2.0, data_power=3.0):
        path = write(mask, self.dir.name)
        mp = sems.mimo_pilot_mapper(path, 2, pilot_power=pilot_power, data_power=data_power)
        data = (np.arange(frames * mp.data_per_frame()) % 7 + 1j).astype(np.complex64)
        src = blocks.vector_source_c(data.tolist())
        sinks = [blocks.vector_sink_c(self.m) for _ in range(2)]
        tb = gr.top_block()
        tb.connect(src, mp)
        for j in range(2):
            tb.connect((mp, j), sinks[j])
        tb.run()
        return mp, data, [np.array(s.data()).reshape(-1, self.n, self.m) for s in sinks], [s.tags() for s in sinks]

    def test_001_each_element_its_pilots_and_every_element_the_data(self):
        for mask in (self.tdm, self.same):
            mp, data, out, tags = self.map_frames(mask)
            self.assertEqual(mp.data_per_frame(), self.n * self.m - 32)
            self.assertEqual(mp.frames(), 2)
            pos = [tuple(p) for p in mask.mask().positions()]
            is_pilot = np.zeros((self.n, self.m), bool)
            for n, m in pos:
                is_pilot[n, m] = True
            for j in range(2):
                self.assertEqual(out[j].shape, (2, self.n, self.m))
                for k, (n, m) in enumerate(pos):
                    self.assertAlmostEqual(out[j][0, n, m], mask.amplitude(k, j) * math.sqrt(2.0), places=6)
                # Data row-major on the other cells, at sqrt(E_d / N_t) on each element.
                np.testing.assert_allclose(out[j][0][~is_pilot], math.sqrt(3.0 / 2) * data[:mp.data_per_frame()],
                                           rtol=1e-6)
                frames = [(t.offset, pmt.to_python(t.value)) for t in tags[j]
                          if pmt.symbol_to_string(t.key) == sems.keys.frame_tag]
                self.assertEqual(frames, [(0, 0), (self.n, 1)])

    def test_002_through_the_emulator_the_extractor_gives_mimo_pilots(self):
        # Pilots only on the mask, zero data: the extractor's observations are the channel's,
        # frame by frame, as mimo_pilots() computes them from the same channel model.
        az = 0.41
        for mask in (self.tdm, self.same):
            path = write(mask, self.dir.name)
            mp = sems.mimo_pilot_mapper(path, 2)
            frames = 2
            src = blocks.vector_source_c([0j] * (frames * mp.data_per_frame()))
            ch = sems.target_channel(scene_text(az), seed=SEED, n_receive=4, n_transmit=2)
            ex = sems.pilot_extractor(mask_file=path, n_elements=4)
            snk = blocks.vector_sink_c(4 * 32)
            tb = gr.top_block()
            tb.connect(src, mp)
            for j in range(2):
                tb.connect((mp, j), (ch, j))
            for k in range(4):
                tb.connect((ch, k), (ex, k))
            tb.connect(ex, snk)
            tb.run()
            got = np.array(snk.data()).reshape(frames, 4 * 32)
            sc = sems.scene.parse(scene_text(az))
            cm = sems.channel_model(self.fs, sc, SEED)
            for f in range(frames):
                want = sems.mimo_pilots(cm, cm.draw(f), f * self.n, mask)
                np.testing.assert_allclose(got[f], want, rtol=1e-5, atol=1e-6)

    def test_003_bad_parameters_are_refused_by_name(self):
        path = write(self.tdm, self.dir.name)
        with self.assertRaisesRegex(ValueError, "n_transmit = 3 but mimo_mask_file .* has n_transmit = 2"):
            sems.mimo_pilot_mapper(path, 3)
        with self.assertRaisesRegex(ValueError, "mimo_mask_file: .*no_such_file.json"):
            sems.mimo_pilot_mapper(os.path.join(self.dir.name, "no_such_file.json"), 2)
        with self.assertRaisesRegex(ValueError, "mimo_mask_file: give"):
            sems.mimo_pilot_mapper("", 2)
        pilot_cols = sorted({m for _, m in (tuple(p) for p in self.tdm.mask().positions())})
        with self.assertRaisesRegex(ValueError, "mimo_pilot_mapper"):
            sems.mimo_pilot_mapper(path, 2, guard_subcarriers=[pilot_cols[0]])
        with self.assertRaisesRegex(ValueError, "pilot_power must be finite and >= 0"):
            sems.mimo_pilot_mapper(path, 2, pilot_power=-1.0)
        mp = sems.mimo_pilot_mapper(path, 2)
        with self.assertRaisesRegex(ValueError, "data_power"):
            mp.set_data_power(math.nan)
        # The one-output mapper refuses a MIMO mask (it would drop the transmit elements); the
        # extractor reads it; a mask whose format is not a string is refused by field.
        with self.assertRaisesRegex(ValueError, "pilot_mapper: mask_file: .*is a MIMO mask .*n_transmit = 2"):
            sems.pilot_mapper(mask_file=path)
        self.assertEqual(sems.pilot_extractor(mask_file=path, n_elements=4).n_pilots(), 32)
        bad = os.path.join(self.dir.name, "bad.json")
        with open(bad, "w") as f:
            json.dump({"format": 1, "version": 1, "n_symbols": 4, "n_subcarriers": 4, "pilots": [[0, 0]]}, f)
        for block in (lambda: sems.pilot_extractor(mask_file=bad, n_symbols=4, n_subcarriers=4),
                      lambda: sems.pilot_mapper(mask_file=bad, n_symbols=4, n_subcarriers=4)):
            with self.assertRaisesRegex(ValueError, "mask_file: .*bad.json: format"):
                block()


if __name__ == "__main__":
    gr_unittest.run(qa_mimo_pilot_mapper)
