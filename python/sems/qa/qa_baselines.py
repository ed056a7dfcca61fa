#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The classical baselines from Python: exact delay recovery on a noiseless on-grid
path drawn by the channel model, the CRB's SNR scaling, Doppler features of a tone,
the feature SVM, and clear errors on bad input."""
import numpy as np
from gnuradio import gr_unittest
from gnuradio import sems


class qa_baselines(gr_unittest.TestCase):
    def setUp(self):
        self.fs = sems.frame_settings()

    def tone(self, mask, f_hz):
        n = np.array([p[0] for p in self.positions(mask)])
        return np.exp(2j * np.pi * f_hz * n * self.fs.symbol_interval_s).astype(np.complex64)

    def positions(self, mask):
        return [tuple(p) for p in mask.positions()]  # (n, m) pairs, mask order

    def path(self, mask, idx, nu):
        pos = self.positions(mask)
        n = np.array([p[0] for p in pos])
        m = np.array([p[1] for p in pos])
        return np.exp(-2j * np.pi * m * idx / self.fs.n_subcarriers
                      + 2j * np.pi * nu * n * self.fs.symbol_interval_s).astype(np.complex64)

    def test_001_delay_estimators_exact_on_grid(self):
        rnd = sems.pilot_mask.random(32, 64, 32, 7)
        obs = self.path(rnd, 23.25, 125.0)
        self.assertAlmostEqual(sems.omp_delay_estimator(self.fs, rnd).estimate_index(obs), 23.25, places=9)
        self.assertAlmostEqual(sems.periodogram_delay_estimator(self.fs, rnd).estimate_index(obs), 23.25, places=4)
        op = sems.nested_subcarrier_mask(32, 64, 32)
        mu = sems.music_delay_estimator(self.fs, op)
        self.assertEqual(mu.coarray_length(), 60)
        self.assertAlmostEqual(mu.estimate_index(self.path(op, 40.5, -300.0)), 40.5, places=9)

    def test_002_crb_scaling(self):
        rnd = sems.pilot_mask.random(32, 64, 32, 7)
        v10 = sems.delay_crb.variance_index(self.fs, rnd, 10.0)
        v20 = sems.delay_crb.variance_index(self.fs, rnd, 20.0)
        self.assertAlmostEqual(v10 / v20, 10.0, places=9)
        self.assertAlmostEqual(sems.delay_crb.mae_index(self.fs, rnd, 10.0), np.sqrt(2 * v10), places=12)

    def test_003_features_and_svm(self):
        mask = sems.pilot_mask.doppler(32, 64, 32)
        fx = sems.doppler_features(self.fs, mask)
        v = fx.extract(self.tone(mask, 5 * 31.25))
        self.assertAlmostEqual(v[0], 156.25, places=4)
        self.assertAlmostEqual(v[4], 156.25, places=6)
        x = [fx.extract(self.tone(mask, f)) for f in (-300, -250, -200, 200, 250, 300)]
        svm = sems.feature_svm(x, [0, 0, 0, 1, 1, 1])
        self.assertEqual(svm.predict(list(fx.extract(self.tone(mask, -275)))), 0)
        self.assertEqual(svm.predict(list(fx.extract(self.tone(mask, 275)))), 1)

    def test_004_bad_input(self):
        rnd = sems.pilot_mask.random(32, 64, 32, 7)
        omp = sems.omp_delay_estimator(self.fs, rnd)
        with self.assertRaises(ValueError):
            omp.estimate_index(np.zeros(31, np.complex64))  # wrong length
        bad = np.ones(32, np.complex64)
        bad[3] = np.nan
        with self.assertRaises(ValueError):
            omp.estimate_index(bad)
        with self.assertRaises(ValueError):
            sems.music_delay_estimator(self.fs, sems.pilot_mask.doppler(32, 64, 32))
        with self.assertRaises(ValueError):
            sems.feature_svm([[0.0], [1.0]], [1, 1])


if __name__ == "__main__":
    gr_unittest.run(qa_baselines)
