#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""position_sink: the shipped position bundle streamed through the block — an array scene
through SemS Target Channel (one output per receive element) and SemS Pilot Extractor (one
input per element) — answers every frame as position_estimator does, scores delay and azimuth
against the truth tag, skips a frame with NaN, and refuses bundles and sizes that do not fit,
naming both values."""
import json
import os

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

K = sems.keys
BUNDLE = os.path.join(os.environ.get("SEMS_SOURCE_DIR", "."), "models", "position_ula8")


def scene_text(azimuths):
    """Random cars of the paper's library seen by the bundle's array (ula8_3g), one path, unfaded."""
    return json.dumps({"format": "sems.scene", "version": 1, "fading": "none", "array": "ula8_3g",
                       "random": {"classes": ["car"], "azimuth_rad": azimuths}})


class qa_position_sink(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.bundle = sems.model_bundle.load(BUNDLE)
        cls.mask = cls.bundle.mask
        cls.n_p = cls.mask.size()
        cls.estimator = sems.position_estimator(BUNDLE, 1)
        cls.k = cls.estimator.n_elements()

    def stream(self, frames, snr_db=20.0, poison=None, batch_size=8):
        """`frames` frames through channel -> extractor -> (optional NaN) -> sink."""
        fs = self.bundle.frame
        n, m = fs.n_symbols, fs.n_subcarriers
        mask = os.path.join(BUNDLE, "mask.json")
        tb = gr.top_block()
        data = blocks.vector_source_c([1 + 0j] * (frames * n * m), False)  # the data cells' symbols
        mapper = sems.pilot_mapper(mask_file=mask)  # the bundle's pilots, with their phases
        head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
        ch = sems.target_channel(scene=scene_text([-0.7, 0.7]), seed=4, n_receive=self.k, snr_db=snr_db)
        ex = sems.pilot_extractor(mask_file=mask, n_elements=self.k)
        sink = sems.position_sink(BUNDLE, self.k, self.n_p, batch_size=batch_size, metrics_period=0)
        pilots = blocks.vector_sink_c(self.k * self.n_p)
        results = blocks.message_debug()
        tb.connect(data, mapper, head, ch)
        for e in range(self.k):
            tb.connect((ch, e), (ex, e))
        last = ex
        if poison is not None:  # a frame with NaN: multiply it by NaN
            gain = [1 + 0j] * (self.k * self.n_p * frames)
            gain[poison * self.k * self.n_p] = complex(float("nan"), 0.0)
            mul = blocks.multiply_vcc(self.k * self.n_p)
            tb.connect(ex, (mul, 0))
            tb.connect(blocks.vector_source_c(gain, False, self.k * self.n_p), (mul, 1))
            last = mul
        tb.connect(last, sink)
        tb.connect(last, pilots)
        tb.msg_connect((sink, K.result_port), (results, "store"))
        tb.run()
        msgs = [pmt.to_python(results.get_message(i)) for i in range(results.num_messages())]
        return sink, msgs, np.asarray(pilots.data()).reshape(frames, self.k * self.n_p)

    def test_answers_are_the_estimators_and_scored_against_the_truth(self):
        sink, results, obs = self.stream(24)
        self.assertEqual(len(results), 24)
        self.assertEqual((sink.frames(), sink.frames_scored(), sink.frames_skipped()), (24, 24, 0))
        want = self.estimator.estimate(obs.astype(np.complex64))
        errors = []
        for r, w in zip(results, want):
            # The polish ends where the spectrum is flat to rounding: the batch a frame went in moves
            # it by ~1e-9 rad, far below the bound (~1e-3 rad).
            self.assertAlmostEqual(r[K.azimuth_rad], w.azimuth_rad, delta=1e-7)
            self.assertAlmostEqual(r[K.delay_index], w.delay_index, delta=1e-5)
            self.assertAlmostEqual(r[K.range_m], w.range_m, delta=1e-4)
            truth = r[K.truth]
            self.assertAlmostEqual(r[K.abs_error_azimuth_rad], abs(r[K.azimuth_rad] - truth[K.azimuth_rad]), places=12)
            self.assertAlmostEqual(r[K.abs_error_index], abs(r[K.delay_index] - truth[K.delay_index]), places=12)
            errors.append(r[K.abs_error_azimuth_rad])
        self.assertEqual(sink.frames_scored_azimuth(), 24)
        self.assertAlmostEqual(sink.rmse_azimuth_rad(), float(np.sqrt(np.mean(np.square(errors)))), places=12)
        # At 20 dB with 8 elements and 32 pilots the bound is below a milliradian; a frame off by
        # more than a hundredth of a radian is a wrong answer, not noise.
        self.assertLess(max(errors), 0.01)
        self.assertLess(sink.mae_index(), 0.5)

    def test_a_frame_with_nan_is_skipped(self):
        sink, results, _ = self.stream(10, poison=3, batch_size=1)  # no partial batch left for stop()
        self.assertEqual((sink.frames(), sink.frames_skipped()), (10, 1))
        self.assertEqual(len(results), 9)
        self.assertNotIn(3, [r[K.frame] for r in results])

    def test_bundles_and_sizes_that_do_not_fit_are_refused(self):
        with self.assertRaisesRegex(ValueError, "array of 8 receive elements, but n_elements = 4"):
            sems.position_sink(BUNDLE, 4, self.n_p)
        with self.assertRaisesRegex(ValueError, "n_elements must be in"):
            sems.position_sink(BUNDLE, 0, self.n_p)
        with self.assertRaisesRegex(ValueError, "not a position bundle"):
            sems.position_sink("delay_single", 8, self.n_p)
        with self.assertRaisesRegex(ValueError, "16"):
            sems.position_sink(BUNDLE, 8, 16)
        with self.assertRaisesRegex(ValueError, "bandwidth_hz differs: the bundle.s frame has 30000000, the stream.s frame has 20000000"):
            sems.position_sink(BUNDLE, 8, self.n_p, frame="sdr_2g4_20mhz")


if __name__ == "__main__":
    gr_unittest.run(qa_position_sink)
