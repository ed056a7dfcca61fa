#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""delay_estimator_sink: a tiny trained bundle streamed through the block (see
testing/sink_contract.py for what both sinks promise) plus the delay answer and its MAE."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testing"))

import numpy as np  # noqa: E402
from gnuradio import gr_unittest, sems  # noqa: E402

import sink_testing as st  # noqa: E402
from sink_contract import K, SinkContract  # noqa: E402


class qa_delay_estimator_sink(SinkContract, gr_unittest.TestCase):
    task, other_task = "delay", "classify"
    exact_keys = ()
    answer_tolerance = 1e-4  # delay index (float32 soft-argmax: ulp(32) = 4e-6); 1e-4 index = 0.5 mm

    @classmethod
    def setUpClass(cls):
        cls.workdir = st.workdir("qa_delay_estimator_sink_")
        cls.bundle = st.tiny_bundle("delay", cls.workdir)
        cls.info, cls.mask = st.bundle_info(cls.bundle)
        cls.n_p = cls.mask.size()
        cls.fs = sems.frame_settings(n_symbols=cls.mask.n_symbols(), n_subcarriers=cls.mask.n_subcarriers())
        cls.obs, cls.truths = st.channel_frames(cls.mask, 40, seed=12, snr_db=20.0)

    def make(self, bundle, n_pilots, **kw):
        return sems.delay_estimator_sink(bundle, n_pilots, **kw)

    def make_other(self, bundle, n_pilots, **kw):
        return sems.classifier_sink(bundle, n_pilots, **kw)

    def answer(self, r):
        return (r[K.delay_index],)

    def reference(self, decoder, obs):
        return [(self.fs.delay_index(d),) for d in decoder.estimate_delay(obs)]

    def check_result(self, r, truth):
        d = r[K.delay_s]
        self.assertTrue(np.isfinite(d))
        self.assertAlmostEqual(r[K.delay_index], d * self.fs.bandwidth_hz, places=9)
        self.assertAlmostEqual(r[K.range_m], d * 3e8 / 2, places=6)
        self.assertAlmostEqual(r[K.abs_error_index], abs(r[K.delay_index] - truth[K.delay_index]), places=12)

    def check_metrics(self, sink, results):
        mae = float(np.mean([r[K.abs_error_index] for r in results]))
        self.assertAlmostEqual(sink.mae_index(), mae, places=12)
        self.assertAlmostEqual(sink.mae_m(), mae * self.fs.range_per_delay_index_m(), places=9)

    def check_running_metric(self, m, results_so_far):
        mae = float(np.mean([r[K.abs_error_index] for r in results_so_far]))
        self.assertAlmostEqual(m[K.mae_index], mae, places=12)
        self.assertAlmostEqual(m[K.mae_m], mae * self.fs.range_per_delay_index_m(), places=9)

    def assert_no_score(self, sink):
        self.assert_nan(sink.mae_index())
        self.assert_nan(sink.mae_m())

    def test_truth_by_delay_seconds(self):
        """A truth with only delay_s is scored in delay indices (delay_s·B); one without a
        delay is not scored."""
        obs = self.obs[:2]
        truths = [{K.delay_s: 100e-9}, {K.class_name: "car"}]
        sink = self.make(self.bundle, self.n_p, batch_size=2, metrics_period=0)
        results, _ = st.run_sink(sink, obs, None, truths, n_metrics=1)
        self.assertAlmostEqual(results[0][K.abs_error_index], abs(results[0][K.delay_index] - 3.0), places=9)
        self.assertNotIn(K.abs_error_index, results[1])
        self.assertEqual(sink.frames_scored(), 1)


if __name__ == "__main__":
    gr_unittest.run(qa_delay_estimator_sink)
