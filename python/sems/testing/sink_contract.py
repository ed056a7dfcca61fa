# SPDX-License-Identifier: GPL-3.0-or-later
"""The behaviour both sinks promise (docs/design.md §3), written once and run by
qa_classifier_sink.py and qa_delay_estimator_sink.py.

A test class mixes SinkContract into gr_unittest.TestCase and provides:
  task            'classify' or 'delay'
  other_task      the task of the other sink
  make(bundle, n_pilots, **kw)   builds the sink under test
  make_other(bundle, n_pilots)   builds the other sink
  answer(result)  the answer of one result dict, as a tuple of floats (compared between runs)
  exact_keys      result keys whose values must match bit for bit across batch sizes
  check_result(result, truth)    task-specific checks of one result against its truth
  check_metrics(sink, results)   the getters against the per-frame results
  reference(decoder, obs)        the answers of bundle_decoder straight on obs (list of tuples)
and in setUpClass: cls.bundle, cls.mask, cls.n_p, cls.obs, cls.truths (see sink_testing).
"""
import math
import os

import numpy as np
from gnuradio import sems

import sink_testing as st

K = sems.keys


class SinkContract:
    answer_tolerance = 1e-5

    # ------------------------------------------------------------------ bookkeeping

    def test_every_frame_one_result_in_order_any_batch(self):
        """batch 1, a batch that does not divide the frame count (partial batch flushed at
        stop()) and one larger than the stream: same frames, same order, same answers."""
        count = len(self.obs)
        indices = list(range(1000, 1000 + count))
        runs = {}
        for batch in (1, 7, 4 * count):
            sink = self.make(self.bundle, self.n_p, batch_size=batch, metrics_period=0)
            results, metrics = st.run_sink(sink, self.obs, indices, self.truths, n_metrics=1)
            self.assertEqual(len(results), count, "batch %d" % batch)
            self.assertEqual([r[K.frame] for r in results], indices, "batch %d" % batch)
            for r, t in zip(results, self.truths):
                self.assertEqual(r[K.truth], t)
                self.check_result(r, t)
            self.assertEqual(sink.frames(), count)
            self.assertEqual(sink.frames_scored(), count)
            self.assertEqual(sink.frames_skipped(), 0)
            self.check_metrics(sink, results)
            self.assertEqual(len(metrics), 1)  # K = 0: once, at the end
            self.assertEqual(metrics[0][K.frames], count)
            runs[batch] = results

        # Exact keys match bit for bit; the answers to float tolerance (a batched matrix
        # product may round differently than one row at a time).
        for batch, results in runs.items():
            for r1, rb in zip(runs[1], results):
                for key in self.exact_keys:
                    self.assertEqual(r1[key], rb[key], "batch %d key %s" % (batch, key))
                np.testing.assert_allclose(self.answer(r1), self.answer(rb), rtol=0, atol=self.answer_tolerance)

    def test_same_answers_as_bundle_decoder(self):
        decoder = st.reference_decoder(self.bundle)
        if decoder is None:
            self.skipTest("gnuradio.sems has no bundle_decoder binding")
        sink = self.make(self.bundle, self.n_p, batch_size=16, metrics_period=0)
        results, _ = st.run_sink(sink, self.obs, None, self.truths, n_metrics=1)
        want = self.reference(decoder, self.obs)
        self.assertEqual(len(results), len(want))
        for r, w in zip(results, want):
            np.testing.assert_allclose(self.answer(r), w, rtol=0, atol=self.answer_tolerance)

    def test_frame_index_counted_without_tag(self):
        count = 12
        indices = [None] * 5 + [500] + [None] * (count - 6)
        sink = self.make(self.bundle, self.n_p, batch_size=5, metrics_period=0)
        results, _ = st.run_sink(sink, self.obs[:count], indices, None, n_metrics=1)
        self.assertEqual([r[K.frame] for r in results], [0, 1, 2, 3, 4] + list(range(500, 500 + count - 5)))
        for r in results:
            self.assertNotIn(K.truth, r)
        self.assertEqual(sink.frames(), count)
        self.assertEqual(sink.frames_scored(), 0)
        self.assert_no_score(sink)

    def test_non_finite_frames_counted_and_skipped(self):
        count = 20
        obs = self.obs[:count].copy()
        bad = {0: complex(np.nan, 0), 3: complex(0, np.inf), 4: complex(-np.inf, np.nan), 19: complex(np.nan, 1)}
        for i, v in bad.items():
            obs[i, i % self.n_p] = v
        indices = list(range(count))
        sink = self.make(self.bundle, self.n_p, batch_size=3, metrics_period=4)
        # Skipped frames count towards K: metrics at frames 4, 8, 12, 16, 20 (the last one
        # already holds the final numbers, so the end of the stream adds none).
        results, metrics = st.run_sink(sink, obs, indices, self.truths[:count], n_metrics=count // 4)
        good = [i for i in indices if i not in bad]
        self.assertEqual([r[K.frame] for r in results], good)
        self.assertEqual(sink.frames(), count)
        self.assertEqual(sink.frames_skipped(), len(bad))
        self.assertEqual(sink.frames_scored(), len(good))
        self.assertEqual([m[K.frames] for m in metrics], [4, 8, 12, 16, 20])
        self.assertEqual(metrics[-1][K.frames_skipped], len(bad))
        # The good frames get the answers they get in a clean stream.
        clean, _ = st.run_sink(self.make(self.bundle, self.n_p, batch_size=1, metrics_period=0),
                               self.obs[:count], indices, self.truths[:count], n_metrics=1)
        clean = [r for r in clean if r[K.frame] not in bad]
        for r, c in zip(results, clean):
            np.testing.assert_allclose(self.answer(r), self.answer(c), rtol=0, atol=self.answer_tolerance)

    def test_metrics_every_k_frames(self):
        count, k = 23, 5
        sink = self.make(self.bundle, self.n_p, batch_size=3, metrics_period=k)
        results, metrics = st.run_sink(sink, self.obs[:count], list(range(count)), self.truths[:count],
                                       n_metrics=count // k + 1)
        self.assertEqual(len(results), count)
        self.assertEqual([m[K.frames] for m in metrics], [5, 10, 15, 20, 23])
        for m in metrics:
            self.assertEqual(m[K.frames_scored], m[K.frames])
            self.assertEqual(m[K.frames_skipped], 0)
            self.check_running_metric(m, results[:m[K.frames]])
        self.assertEqual(sink.metrics_period(), k)
        sink.set_metrics_period(0)
        self.assertEqual(sink.metrics_period(), 0)
        self.assertRaises(ValueError, sink.set_metrics_period, -1)
        sink.reset_metrics()
        self.assertEqual((sink.frames(), sink.frames_scored(), sink.frames_skipped()), (0, 0, 0))
        self.assert_no_score(sink)

    # ------------------------------------------------------------------ refusals

    def assert_refused(self, what, *fragments, **kw):
        bundle = kw.pop("bundle", self.bundle)
        n_p = kw.pop("n_pilots", self.n_p)
        make = kw.pop("make", self.make)
        with self.assertRaises(ValueError, msg=what) as ctx:
            make(bundle, n_p, **kw)
        msg = str(ctx.exception)
        for f in fragments:
            self.assertIn(f, msg, "%s: %r lacks %r" % (what, msg, f))
        return msg

    def test_refuses_mismatched_bundles(self):
        name = "classifier_sink" if self.task == "classify" else "delay_estimator_sink"
        self.assert_refused("wrong N_p", name, self.bundle, n_pilots=self.n_p + 1)
        self.assert_refused("wrong N", name, self.bundle, n_symbols=self.mask.n_symbols() * 2)
        self.assert_refused("wrong M", name, self.bundle, n_subcarriers=self.mask.n_subcarriers() + 1)
        missing = os.path.join(self.workdir, "no_such_bundle")
        self.assert_refused("missing directory", name, missing, bundle=missing)
        self.assert_refused("no directory", name, "bundle", bundle="")
        # This sink's bundle given to the other sink, and a bundle relabelled as the other task.
        other = "delay_estimator_sink" if self.task == "classify" else "classifier_sink"
        self.assert_refused("wrong task for the sink", other, self.bundle, make=self.make_other)
        relabelled = st.copy_bundle(self.bundle, self.workdir, "relabelled",
                                    lambda j: j.__setitem__("task", self.other_task))
        self.assert_refused("bundle of the other task", name, relabelled, bundle=relabelled)

    def test_refuses_a_bundle_of_another_frame_in_any_field(self):
        """The bundle's frame is compared with the stream's in every field (N and M above; here
        B, f_c, T, CP and the guards): a copy whose frame differs in one is refused naming the
        field, the bundle's value and the stream's."""
        name = "classifier_sink" if self.task == "classify" else "delay_estimator_sink"
        used = {m for _, m in self.mask.positions()}
        guard = next(m for m in range(self.mask.n_subcarriers()) if m not in used)
        for field, value, mine, theirs in (("bandwidth_hz", 20e6, "20000000", "30000000"),
                                           ("carrier_hz", 2.4e9, "2400000000", "3000000000"),
                                           ("symbol_interval_s", 5e-4, "0.0005", "0.001"),
                                           ("cp_len", 32, "32", "16"),
                                           ("guard_subcarriers", [guard], "[%d]" % guard, "none")):
            copy = st.copy_bundle(self.bundle, self.workdir, "frame_" + field,
                                  lambda j: j["frame"].__setitem__(field, value))
            self.assert_refused(field, name, "frame field %s differs: the bundle's frame has %s, the stream's "
                                "frame has %s" % (field, mine, theirs), bundle=copy)

    def test_refuses_bad_parameters(self):
        self.assert_refused("batch 0", "batch_size", batch_size=0)
        self.assert_refused("negative threads", "threads", threads=-1)
        self.assert_refused("negative K", "metrics_period", metrics_period=-1)
        self.assert_refused("no pilots", "n_pilots", n_pilots=0)

    # ------------------------------------------------------------------ helpers

    def assert_nan(self, x):
        self.assertTrue(math.isnan(x), "expected NaN, got %r" % x)
