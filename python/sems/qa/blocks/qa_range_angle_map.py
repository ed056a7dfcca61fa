#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: range_angle_map. The array chain (target channel with one output per element, the
pilot extractor over every element, the map) puts a target on its azimuth row and delay
column; tags follow their frame; a NaN frame is skipped and counted; bad parameters are
refused by name."""
import json
import math

import numpy as np
from gnuradio import blocks, gr, gr_unittest, sems

ARRAY = {"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 8, "spacing_m": 0.05}}}


def chain(az, frames=2):
    fs = sems.frame_settings()
    n, m = fs.n_symbols, fs.n_subcarriers
    scene = {"format": "sems.scene", "version": 1, "array": {"receive": ARRAY["receive"]},
             "targets": [{"class": "car", "range_m": 45, "velocity_mps": 9, "azimuth_rad": az}]}
    mask = sems.pilot_mask.uniform(n, m, 128)
    positions = mask.flat_indices()
    tb = gr.top_block()
    src = blocks.vector_source_c([1 + 0j] * (frames * n * m), False, m)
    ch = sems.target_channel(scene=json.dumps(scene), seed=1, snr_db=20.0, n_receive=8)
    ex = sems.pilot_extractor(pilot_positions=positions, n_elements=8)
    ra = sems.range_angle_map(json.dumps(ARRAY), pilot_positions=positions, n_angles=64)
    snk = blocks.vector_sink_f(64 * m)
    tb.connect(src, ch)
    for k in range(8):
        tb.connect((ch, k), (ex, k))
    tb.connect(ex, ra, snk)
    tb.run()
    return ra, snk


class qa_range_angle_map(gr_unittest.TestCase):

    def test_target_on_its_row_and_column(self):
        # 45 m is delay index 9 at 30 MHz; the row nearest the azimuth holds the peak.
        for az in (-0.6, 0.0, 0.35):
            ra, snk = chain(az)
            self.assertEqual((ra.n_elements(), ra.n_pilots(), ra.n_angles(), ra.frames_out()), (8, 128, 64, 2))
            maps = np.array(snk.data()).reshape(2, 64, -1)
            row, col = np.unravel_index(np.argmax(maps[0]), maps[0].shape)
            self.assertEqual(col, 9)
            self.assertLessEqual(abs(-math.pi / 2 + math.pi * (row + 0.5) / 64 - az), math.pi / 64)
            self.assertEqual(len([t for t in snk.tags() if str(t.key) == "sems_truth"]), 2)

    def test_nonfinite_frame_skipped(self):
        positions = list(range(4))
        y = np.ones(2 * 8 * 4, np.complex64)
        y[5] = np.nan
        tb = gr.top_block()
        src = blocks.vector_source_c(y.tolist(), False, 8 * 4)
        ra = sems.range_angle_map(json.dumps(ARRAY), pilot_positions=positions)
        snk = blocks.vector_sink_f(64 * 64)
        tb.connect(src, ra, snk)
        tb.run()
        self.assertEqual((ra.frames_out(), ra.frames_skipped_nonfinite()), (1, 1))

    def test_bad_parameters_are_refused_by_name(self):
        with self.assertRaisesRegex(ValueError, "array is empty"):
            sems.range_angle_map("", pilot_positions=[0])
        with self.assertRaisesRegex(ValueError, "array JSON text does not parse"):
            sems.range_angle_map("{nope", pilot_positions=[0])
        with self.assertRaisesRegex(ValueError, "n_angles must be in"):
            sems.range_angle_map(json.dumps(ARRAY), pilot_positions=[0], n_angles=1)
        with self.assertRaisesRegex(ValueError, "carrier_hz"):
            sems.range_angle_map(json.dumps(ARRAY), pilot_positions=[0], carrier_hz=0.0)
        with self.assertRaisesRegex(ValueError, "no_such_array.json"):
            sems.range_angle_map("no_such_array.json", pilot_positions=[0])
        # A preset's name is the same array as its JSON text (ula8_3g: 8 elements 5 cm apart).
        self.assertEqual(sems.range_angle_map("ula8_3g", pilot_positions=[0]).n_elements(), 8)


if __name__ == "__main__":
    gr_unittest.run(qa_range_angle_map)
