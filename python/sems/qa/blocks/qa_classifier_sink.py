#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""classifier_sink: a tiny trained bundle streamed through the block (see testing/sink_contract.py
for what both sinks promise) plus the classifier's own answer and metrics."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testing"))

import numpy as np  # noqa: E402
from gnuradio import gr_unittest, sems  # noqa: E402

import sink_testing as st  # noqa: E402
from sink_contract import K, SinkContract  # noqa: E402


class qa_classifier_sink(SinkContract, gr_unittest.TestCase):
    task, other_task = "classify", "delay"
    exact_keys = (K.label, K.class_name, K.correct)

    @classmethod
    def setUpClass(cls):
        cls.workdir = st.workdir("qa_classifier_sink_")
        cls.bundle = st.tiny_bundle("classify", cls.workdir)
        cls.info, cls.mask = st.bundle_info(cls.bundle)
        cls.names = cls.info["class_names"]
        cls.n_p = cls.mask.size()
        cls.obs, cls.truths = st.channel_frames(cls.mask, 40, seed=11, snr_db=20.0)

    def make(self, bundle, n_pilots, **kw):
        return sems.classifier_sink(bundle, n_pilots, **kw)

    def make_other(self, bundle, n_pilots, **kw):
        return sems.delay_estimator_sink(bundle, n_pilots, **kw)

    def answer(self, r):
        return tuple(r[K.probs])

    def reference(self, decoder, obs):
        probs = np.asarray(decoder.classify(obs)).reshape(len(obs), -1)
        return [tuple(p) for p in probs]

    def check_result(self, r, truth):
        probs = np.asarray(r[K.probs])
        self.assertEqual(len(probs), len(self.names))
        self.assertTrue(np.all(np.isfinite(probs)) and np.all(probs >= 0))
        self.assertAlmostEqual(float(np.sum(probs)), 1.0, places=5)
        self.assertEqual(r[K.label], int(np.argmax(probs)))
        self.assertEqual(r[K.class_name], self.names[r[K.label]])
        self.assertEqual(r[K.correct], truth[K.class_name] == r[K.class_name])

    def check_metrics(self, sink, results):
        correct = [r[K.correct] for r in results]
        self.assertAlmostEqual(sink.accuracy(), float(np.mean(correct)), places=12)
        self.assertEqual(sink.class_names(), self.names)
        conf = np.asarray(sink.confusion())
        self.assertEqual(conf.shape, (len(self.names), len(self.names)))
        want = np.zeros_like(conf)
        for r in results:
            want[self.names.index(r[K.truth][K.class_name]), r[K.label]] += 1
        np.testing.assert_array_equal(conf, want)
        self.assertEqual(int(np.trace(conf)), int(np.sum(correct)))

    def check_running_metric(self, m, results_so_far):
        self.assertAlmostEqual(m[K.accuracy], float(np.mean([r[K.correct] for r in results_so_far])), places=12)
        conf = np.array([list(row) for row in m[K.confusion]])
        self.assertEqual(int(conf.sum()), len(results_so_far))

    def assert_no_score(self, sink):
        self.assert_nan(sink.accuracy())
        self.assertEqual(int(np.sum(sink.confusion())), 0)

    def test_truth_by_class_id_and_unknown_class(self):
        """A truth with only a class id is scored through the class table; a class the
        bundle does not know is scored as wrong and has no confusion row; a truth
        without a class is not scored."""
        obs = self.obs[:3]
        truths = [{K.class_id: 1}, {K.class_name: "submarine"}, {K.delay_index: 3.0}]
        sink = self.make(self.bundle, self.n_p, batch_size=2, metrics_period=0)
        results, _ = st.run_sink(sink, obs, None, truths, n_metrics=1)
        self.assertEqual(results[0][K.correct], results[0][K.class_name] == sems.class_names()[1])
        self.assertFalse(results[1][K.correct])
        self.assertNotIn(K.correct, results[2])
        self.assertEqual(sink.frames_scored(), 2)
        self.assertEqual(int(np.sum(sink.confusion())), 1 if "car" in self.names else 0)


if __name__ == "__main__":
    gr_unittest.run(qa_classifier_sink)
