#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The core library from Python: frame settings, masks, scenes, channel model as numpy."""
import json
import math
import os
import tempfile

import numpy as np
from gnuradio import gr_unittest, sems
from gnuradio.sems import datasets


class qa_core_bindings(gr_unittest.TestCase):

    def test_frame_settings_defaults_and_derived(self):
        fs = sems.frame_settings()
        self.assertEqual((fs.n_symbols, fs.n_subcarriers, fs.cp_len), (32, 64, 16))
        self.assertAlmostEqual(fs.subcarrier_spacing_hz(), 468.75e3)
        self.assertAlmostEqual(fs.wavelength_m(), 0.1)
        self.assertAlmostEqual(fs.max_range_m(), 320.0)
        self.assertAlmostEqual(fs.max_doppler_hz(), 500.0)
        self.assertAlmostEqual(fs.range_per_delay_index_m(), 5.0)
        with self.assertRaisesRegex(ValueError, "bandwidth_hz"):
            sems.frame_settings(bandwidth_hz=-1.0)

    def test_mask_patterns_and_round_trip(self):
        mask = sems.pilot_mask.uniform(32, 64, 32)
        self.assertEqual(len(mask), 32)
        self.assertEqual(mask.positions(), sorted(mask.positions()))
        self.assertEqual(int(mask.dense().sum()), 32)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "mask.json")
            mask.save(path)
            with open(path) as f:
                self.assertEqual(json.load(f)["format"], "sems.pilot_mask")
            self.assertTrue(sems.pilot_mask.load(path) == mask)
        with self.assertRaisesRegex(ValueError, "duplicate"):
            sems.pilot_mask(4, 8, [(0, 1), (0, 1)])

    def test_generate_matches_realization(self):
        scene = sems.scene.random()
        model = sems.channel_model(sems.frame_settings(), scene, 3)
        h, truths = model.generate(4, 10)
        self.assertEqual(h.shape, (4, 32, 64))
        self.assertEqual(h.dtype, np.complex64)
        self.assertEqual([t["frame"] for t in truths], [10, 11, 12, 13])
        # The same seed drawn frame by frame gives the same grids.
        again = sems.channel_model(sems.frame_settings(), scene, 3)
        for k in range(4):
            r = again.draw(10 + k)
            np.testing.assert_array_equal(again.channel(r, (10 + k) * 32), h[k])
            self.assertEqual(r.truth["class_name"], truths[k]["class_name"])
        self.assertAlmostEqual(truths[0]["delay_index"], truths[0]["delay_s"] * 30e6, places=9)

    def test_fixed_scene_phase_slope(self):
        text = json.dumps({"format": "sems.scene", "version": 1, "fading": "none",
                           "targets": [{"class": "car", "range_m": 45.0, "velocity_mps": 12.0}]})
        model = sems.channel_model(sems.frame_settings(), sems.scene.parse(text), 0)
        h, _ = model.generate(1)
        slope = np.angle(h[0, 0, 1:] * np.conj(h[0, 0, :-1]))
        expected = -2 * math.pi * 468.75e3 * (2 * 45.0 / 3e8)
        np.testing.assert_allclose(np.angle(np.exp(1j * (slope - expected))), 0, atol=1e-5)

    def test_batches_with_noise(self):
        scene = sems.scene.random()
        clean = next(datasets.channel_batches(scene, 64, seed=5))[0]
        noisy, truths = next(datasets.channel_batches(scene, 64, seed=5, snr_db=10.0))
        noise = noisy - clean
        self.assertAlmostEqual(10 * math.log10(1.0 / np.mean(np.abs(noise) ** 2)), 10.0, delta=0.1)
        self.assertEqual(truths[0]["snr_db"], 10.0)
        self.assertEqual(datasets.stack_truths(truths, sems.keys.frame).tolist(), list(range(64)))

    def test_keys_are_the_design_names(self):
        self.assertEqual(sems.keys.frame_tag, "sems_frame")
        self.assertEqual(sems.keys.truth_tag, "sems_truth")
        self.assertEqual(sems.class_names(), ["pedestrian", "car", "drone"])


if __name__ == "__main__":
    gr_unittest.run(qa_core_bindings)
