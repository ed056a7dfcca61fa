#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Extremes end to end through both sinks (the shipped bundles): SNR -50 dB, +300 dB
and noiseless through mapper -> channel -> extractor -> sinks; pilot observations
scaled by 1e+20 and 1e-20; NaN/Inf bursts. Every answer is finite, or the frame is a
counted skip; every frame is accounted for (frames = scored + skipped)."""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))

import numpy as np  # noqa: E402
from gnuradio import blocks, gr, gr_unittest, sems  # noqa: E402

import sink_testing as st  # noqa: E402

MODELS = os.path.join(st.SOURCE_DIR, "models")
CLS = os.path.join(MODELS, "classifier")
DLY = os.path.join(MODELS, "delay_single")


def sinks(batch=16, metrics_period=0):
    c_mask = sems.pilot_mask.load(os.path.join(CLS, "mask.json"))
    d_mask = sems.pilot_mask.load(os.path.join(DLY, "mask.json"))
    c = sems.classifier_sink(CLS, c_mask.size(), batch_size=batch, threads=1, metrics_period=metrics_period)
    d = sems.delay_estimator_sink(DLY, d_mask.size(), batch_size=batch, threads=1, metrics_period=metrics_period)
    return c, d, c_mask, d_mask


class qa_extremes(gr_unittest.TestCase):
    def assert_accounted(self, sink, frames):
        self.assertEqual(sink.frames(), frames)
        self.assertEqual(sink.frames_scored() + sink.frames_skipped(), frames)

    def assert_finite_results(self, results, key):
        for r in results:
            v = r[key]
            arr = np.atleast_1d(np.asarray(v, dtype=float))
            self.assertTrue(np.all(np.isfinite(arr)), "%s = %r" % (key, v))

    def test_chain_at_extreme_snr(self):
        n_frames = 48
        for snr in (-50.0, 300.0, math.inf):
            with self.subTest(snr=snr):
                c, d, c_mask, d_mask = sinks()
                n, m = c_mask.n_symbols(), c_mask.n_subcarriers()
                tb = gr.top_block()
                mapper = sems.pilot_mapper(pilot_positions=list(range(n * m)), n_symbols=n, n_subcarriers=m)
                head = blocks.head(gr.sizeof_gr_complex * m, n_frames * n)
                channel = sems.target_channel(snr_db=snr, seed=5, n_symbols=n, n_subcarriers=m)
                ex_c = sems.pilot_extractor(mask_file=os.path.join(CLS, "mask.json"), n_symbols=n, n_subcarriers=m)
                ex_d = sems.pilot_extractor(mask_file=os.path.join(DLY, "mask.json"), n_symbols=n, n_subcarriers=m)
                tb.connect(mapper, head, channel, ex_c, c)
                tb.connect(channel, ex_d, d)
                tb.run()
                for sink in (c, d):
                    self.assert_accounted(sink, n_frames)
                    self.assertEqual(sink.frames_faulted(), 0)
                # Every frame is finite here: all scored, and the metrics are finite numbers.
                self.assertEqual(c.frames_scored(), n_frames)
                self.assertTrue(0.0 <= c.accuracy() <= 1.0)
                self.assertTrue(math.isfinite(d.mae_index()))
                if snr >= 300.0:  # (nearly) noiseless: the shipped models are right most of the time
                    self.assertGreater(c.accuracy(), 0.6)

    def test_amplitudes_1e_pm20(self):
        c_mask = sems.pilot_mask.load(os.path.join(CLS, "mask.json"))
        d_mask = sems.pilot_mask.load(os.path.join(DLY, "mask.json"))
        for scale in (1e20, 1e-20):
            with self.subTest(scale=scale):
                c, d, _, _ = sinks()
                for sink, mask, key in ((c, c_mask, sems.keys.probs), (d, d_mask, sems.keys.delay_index)):
                    obs, truths = st.channel_frames(mask, 24, seed=3, snr_db=20.0)
                    obs = (obs * np.float32(scale)).astype(np.complex64)
                    self.assertTrue(np.all(np.isfinite(obs.view(np.float32))))
                    results, _ = st.run_sink(sink, obs, truths=truths)
                    self.assertEqual(len(results), 24)
                    self.assert_finite_results(results, key)
                    self.assert_accounted(sink, 24)
                    self.assertEqual(sink.frames_skipped(), 0)

    def test_nan_inf_bursts(self):
        c, d, c_mask, d_mask = sinks(batch=8, metrics_period=10)
        for sink, mask, key in ((c, c_mask, sems.keys.probs), (d, d_mask, sems.keys.delay_index)):
            obs, truths = st.channel_frames(mask, 60, seed=9, snr_db=10.0)
            bad = list(range(5, 12)) + list(range(30, 33)) + [59]  # bursts, and the last frame
            for k, i in enumerate(bad):
                obs[i, k % mask.size()] = [np.nan, np.inf, -np.inf][k % 3]
            obs[20:23, :] = np.inf  # whole frames
            bad += [20, 21, 22]
            results, metrics = st.run_sink(sink, obs, truths=truths, n_metrics=6)
            self.assertEqual(len(results), 60 - len(bad))
            self.assertEqual(sorted(r[sems.keys.frame] for r in results),
                             [i for i in range(60) if i not in bad])
            self.assert_finite_results(results, key)
            self.assertEqual(sink.frames_skipped(), len(bad))
            self.assertEqual(sink.frames_faulted(), 0)
            self.assert_accounted(sink, 60)
            self.assertEqual(metrics[-1][sems.keys.frames_skipped], len(bad))


if __name__ == "__main__":
    gr_unittest.run(qa_extremes)
