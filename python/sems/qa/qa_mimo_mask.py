#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""MIMO masks from Python (core/array/mimo_mask.h): the hand forms against their definitions,
the file and its text, errors by field; the azimuth bound and the maximum-likelihood estimator
of baselines/mimo_angle.h on the emulator's pilots; and a tiny run of the mask learner
(learning/array/mimo_mask_learner.h)."""
import json
import math
import os
import tempfile

import numpy as np
from gnuradio import gr_unittest, sems
# The extensions themselves, not the package's lazy names: these tests do not depend on
# gnuradio.sems's name lists (qa_lazy_import checks those).
from gnuradio.sems import baselines_python as baselines
from gnuradio.sems import learning_python as learning

ARRAY = "mimo2x4_3g"  # 4 receive and 2 transmit elements (models/arrays/mimo2x4_3g.json)


class qa_mimo_mask(gr_unittest.TestCase):

    def setUp(self):
        self.fs = sems.frame_settings()
        self.pilots = sems.pilot_mask.from_pattern("uniform", self.fs, 32)
        self.tdm = sems.mimo_mask.time_division(self.pilots, 2)

    def test_001_hand_forms(self):
        pos = [tuple(p) for p in self.pilots.positions()]  # (n, m), mask order
        # Time division: the symbols holding pilots, in increasing order, go to elements 0, 1, 0, ...
        symbols = sorted({n for n, _ in pos})
        self.assertGreaterEqual(len(symbols), 2)
        self.assertEqual(self.tdm.n_transmit(), 2)
        self.assertEqual(len(self.tdm), 32)
        self.assertTrue(self.tdm.mask() == self.pilots)
        self.assertEqual(self.tdm.transmit(), [symbols.index(n) % 2 for n, _ in pos])
        self.assertEqual(sum(self.tdm.pilots_per_element()), 32)
        for k, t in enumerate(self.tdm.transmit()):
            self.assertEqual([self.tdm.amplitude(k, j) for j in range(2)], [1.0 if j == t else 0.0 for j in range(2)])
        # Frequency division: the same by subcarrier.
        carriers = sorted({m for _, m in pos})
        fdm = sems.mimo_mask.frequency_division(self.pilots, 2)
        self.assertEqual(fdm.transmit(), [carriers.index(m) % 2 for _, m in pos])
        # Same pilots: every pilot from every element at 1/sqrt(N_t).
        same = sems.mimo_mask.same_pilots(self.pilots, 2)
        self.assertEqual(sems.mimo_mask.every_element, -1)
        self.assertEqual(same.transmit(), [-1] * 32)
        self.assertEqual(same.pilots_per_element(), [0, 0])
        for k in range(32):
            for j in range(2):
                self.assertAlmostEqual(same.amplitude(k, j), 1.0 / math.sqrt(2.0), places=15)
        self.assertFalse(same == self.tdm)
        # Time division needs a symbol per element.
        one_symbol = sems.pilot_mask(4, 8, [(1, 0), (1, 3), (1, 5)])
        with self.assertRaisesRegex(ValueError, "fewer than the 2 transmit elements"):
            sems.mimo_mask.time_division(one_symbol, 2)

    def test_002_file_and_text_round_trip(self):
        mixed = sems.mimo_mask(self.pilots, 2, [(-1, 0, 1)[k % 3] for k in range(32)], "mixed")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "mimo_mask.json")
            mixed.save(path)
            with open(path) as f:
                j = json.load(f)
            self.assertEqual((j["format"], j["version"], j["n_transmit"]), (sems.mimo_mask.format_name, 1, 2))
            self.assertEqual(j["format"], "sems.mimo_mask")
            self.assertTrue(sems.mimo_mask.load(path) == mixed)
        self.assertTrue(sems.mimo_mask.parse(mixed.to_json_string()) == mixed)
        self.assertTrue(sems.mimo_mask.parse(self.tdm.to_json_string()) == self.tdm)

    def test_003_bad_transmit_entries_are_refused_by_field(self):
        with self.assertRaisesRegex(ValueError, r"transmit\[31\].*got 2"):
            sems.mimo_mask(self.pilots, 2, [0] * 31 + [2])
        with self.assertRaisesRegex(ValueError, "transmit.*31 entries.*32 pilots"):
            sems.mimo_mask(self.pilots, 2, [0] * 31)
        with self.assertRaisesRegex(ValueError, "n_transmit"):
            sems.mimo_mask(self.pilots, 0, [0] * 32)
        j = json.loads(self.tdm.to_json_string())
        j["transmit"][3] = 5
        with self.assertRaisesRegex(ValueError, r"my mask.*transmit\[3\]"):
            sems.mimo_mask.parse(json.dumps(j), "my mask")
        with self.assertRaises(IndexError):
            self.tdm.amplitude(32, 0)

    def test_004_crb(self):
        a = sems.array_geometry.find(ARRAY)
        self.assertEqual((a.n_receive(), a.n_transmit()), (4, 2))
        same = sems.mimo_mask.same_pilots(self.pilots, 2)
        td = baselines.mimo_angle_crb_rad2(a, self.tdm, self.fs, 0.5, 0.0, 1.0)
        sp = baselines.mimo_angle_crb_rad2(a, same, self.fs, 0.5, 0.0, 1.0)
        self.assertTrue(math.isfinite(td) and td > 0.0, td)
        self.assertTrue(math.isfinite(sp) and sp > 0.0, sp)
        self.assertGreater(sp, td)  # the same pilots lose the virtual array's aperture
        # It falls as 1/SNR.
        self.assertAlmostEqual(baselines.mimo_angle_crb_rad2(a, self.tdm, self.fs, 0.5, 0.0, 10.0) / td, 0.1, places=12)
        with self.assertRaisesRegex(ValueError, "snr"):
            baselines.mimo_angle_crb_rad2(a, self.tdm, self.fs, 0.5, 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, "2 transmit elements.*the MIMO mask 3"):
            baselines.mimo_angle_crb_rad2(a, sems.mimo_mask.same_pilots(self.pilots, 3), self.fs, 0.5, 0.0, 1.0)

    def test_005_maximum_likelihood_finds_the_emulated_target(self):
        a = sems.array_geometry.find(ARRAY)
        az = 0.37
        t = sems.target_spec(sems.target_class.car, 60.0, 8.0, azimuth_rad=az)
        cm = sems.channel_model(self.fs, sems.scene.fixed([t], fading=sems.fading_kind.none).with_array(a), 1)
        r = cm.draw(0)
        y = sems.mimo_pilots(cm, r, 0, self.tdm)
        self.assertEqual(y.shape, (4 * 32,))
        self.assertEqual(y.dtype, np.complex64)
        ml = baselines.mimo_ml_angle_estimator(a, self.tdm, self.fs, 0.0, baselines.angle_search(-1.0, 1.0, 64), 2)
        e = ml.estimate(y)
        self.assertAlmostEqual(e.azimuth_rad, az, delta=1e-6)
        self.assertTrue(0.0 <= e.delay_index < self.fs.n_subcarriers)
        self.assertTrue(-self.fs.n_symbols / 2 <= e.doppler_bins < self.fs.n_symbols / 2)
        # The estimate is the likelihood's maximum.
        best = ml.likelihood(y, e.azimuth_rad, e.delay_index, e.doppler_bins)
        self.assertGreater(best, ml.likelihood(y, az + 0.05, e.delay_index, e.doppler_bins))
        # Observations of the wrong length are refused with both counts.
        with self.assertRaisesRegex(ValueError, r"N_r·N_p = 4·32 = 128 .*got a 1-D array of 127 values"):
            ml.estimate(y[:-1])
        with self.assertRaisesRegex(ValueError, "128.*2-D array of 128 values"):
            ml.estimate(y.reshape(4, 32))
        with self.assertRaisesRegex(ValueError, "likelihood.*128"):
            ml.likelihood(y[:64], az, 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, "not finite"):
            bad = y.copy()
            bad[5] = np.nan
            ml.estimate(bad)
        # A mask of another frame, or of another transmit count, is refused.
        with self.assertRaisesRegex(ValueError, "mimo_pilots"):
            sems.mimo_pilots(cm, r, 0, sems.mimo_mask.same_pilots(sems.pilot_mask.uniform(8, 16, 8), 2))
        with self.assertRaisesRegex(ValueError, "2 transmit elements and the MIMO mask 3"):
            sems.mimo_pilots(cm, r, 0, sems.mimo_mask.same_pilots(self.pilots, 3))

    def test_006_learner(self):
        s = learning.mimo_mask_settings()
        self.assertEqual(s.array, ARRAY)
        s.frame.n_symbols = 8
        s.frame.n_subcarriers = 16
        s.n_pilots = 8
        s.epochs = 2
        s.steps = 2
        s.draws = 8
        s.eval_azimuths = 21
        s.seed = 5
        s.threads = 1
        s.verbose = False
        s.validate()
        r = learning.learn_mimo_mask(s)
        self.assertEqual(len(r.mask.mask()), 8)
        self.assertEqual(r.mask.n_transmit(), 2)
        self.assertTrue(all(t in (0, 1) for t in r.mask.transmit()), r.mask.transmit())
        self.assertGreater(r.mean_crb_rad2, 0.0)
        self.assertTrue(math.isfinite(r.mean_crb_rad2))
        self.assertEqual(len(json.loads(r.history_json)), 2)
        a = sems.array_geometry.find(ARRAY)
        objective = learning.mimo_mean_crb_rad2(a, r.mask, s.frame, s.azimuth_min_rad, s.azimuth_max_rad,
                                                s.eval_azimuths)
        self.assertAlmostEqual(r.mean_crb_rad2 / objective, 1.0, places=9)
        s.n_pilots = 1
        with self.assertRaisesRegex(ValueError, "n_pilots"):
            learning.learn_mimo_mask(s)


if __name__ == "__main__":
    gr_unittest.run(qa_mimo_mask)
