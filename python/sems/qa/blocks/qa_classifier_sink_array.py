#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""classifier_sink over an array: the kinematic classifier (trained on one antenna) streamed
from an 8-element ULA — SemS Target Channel's eight outputs into SemS Pilot Extractor's eight
inputs into the sink — beamforms each frame towards the peak of its beamforming spectrum
(computed here from the array's geometry alone) and answers as the one-antenna sink does on
those pilots; the azimuth follows the truth; array and count mismatches are refused by name."""
import json
import os

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

K = sems.keys
SOURCE = os.environ.get("SEMS_SOURCE_DIR", ".")
BUNDLE = os.path.join(SOURCE, "models", "classifier_kinematic")
ARRAY = "ula8_3g"  # 8 elements 5 cm apart along y, centred (models/arrays/ula8_3g.json)
C = 3e8  # the module's speed of light (frame_settings.h: the paper's value)


def scene_text(azimuths, track_frames=0):
    """The kinematic library's targets, any heading, seen by ula8_3g from `azimuths` (on tracks of
    `track_frames` frames crossing the line of sight, when given)."""
    random = {"heading": "any", "azimuth_rad": azimuths}
    if track_frames:
        random["tracks"] = {"frames": track_frames, "motion": "straight"}
    return json.dumps({"format": "sems.scene", "version": 1, "classes": "kinematic", "array": ARRAY,
                       "random": random})


def beamformed(obs, k, lam, azimuths):
    """Each frame's k x N_p pilots combined towards its azimuth, z = aᴴy/‖a‖², with a ULA's steering
    vector written from its geometry: element e at y_e = (e − (k−1)/2)·0.05 m gains exp(j2π y_e sin φ/λ)."""
    y_e = (np.arange(k) - (k - 1) / 2.0) * 0.05
    out = []
    for frame, az in zip(obs, azimuths):
        a = np.exp(2j * np.pi * y_e * np.sin(az) / lam)
        out.append(a.conj() @ frame.reshape(k, -1).astype(np.complex128) / k)
    return np.asarray(out, dtype=np.complex64)


class qa_classifier_sink_array(gr_unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.bundle = sems.model_bundle.load(BUNDLE)
        cls.mask = cls.bundle.mask
        cls.n_p = cls.mask.size()
        cls.k = 8
        fs = cls.bundle.frame
        spacing = fs.bandwidth_hz / fs.n_subcarriers
        mean_m = np.mean([m for _, m in cls.mask.positions()])  # (symbol, subcarrier) pairs
        cls.lam = C / (fs.carrier_hz + mean_m * spacing)  # the pilots' mean frequency's wavelength

    def stream(self, frames, snr_db=20.0, bundle=BUNDLE, track_frames=0):
        fs = self.bundle.frame
        n, m = fs.n_symbols, fs.n_subcarriers
        mask = os.path.join(BUNDLE, "mask.json")
        tb = gr.top_block()
        data = blocks.vector_source_c([1 + 0j] * (frames * n * m), False)
        mapper = sems.pilot_mapper(mask_file=mask)
        head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
        ch = sems.target_channel(scene=scene_text([-0.7, 0.7], track_frames), seed=7, n_receive=self.k, snr_db=snr_db)
        ex = sems.pilot_extractor(mask_file=mask, n_elements=self.k)
        sink = sems.classifier_sink(bundle, self.n_p, batch_size=8, metrics_period=0, n_elements=self.k, array=ARRAY)
        pilots = blocks.vector_sink_c(self.k * self.n_p)
        results = blocks.message_debug()
        tb.connect(data, mapper, head, ch)
        for e in range(self.k):
            tb.connect((ch, e), (ex, e))
        tb.connect(ex, sink)
        tb.connect(ex, pilots)
        tb.msg_connect((sink, K.result_port), (results, "store"))
        tb.run()
        msgs = [pmt.to_python(results.get_message(i)) for i in range(results.num_messages())]
        return sink, msgs, np.asarray(pilots.data()).reshape(frames, self.k * self.n_p)

    def one_antenna(self, pilots, bundle=BUNDLE):
        """The one-antenna sink's answers on pilots given frame by frame."""
        tb = gr.top_block()
        src = blocks.vector_source_c(pilots.reshape(-1).tolist(), False, self.n_p)
        sink = sems.classifier_sink(bundle, self.n_p, batch_size=8, metrics_period=0)
        results = blocks.message_debug()
        tb.connect(src, sink)
        tb.msg_connect((sink, K.result_port), (results, "store"))
        tb.run()
        return [pmt.to_python(results.get_message(i)) for i in range(results.num_messages())]

    def test_answers_are_the_one_antenna_sinks_on_the_beamformed_pilots(self):
        frames = 32
        sink, results, obs = self.stream(frames)
        self.assertEqual(sink.n_elements(), self.k)
        self.assertEqual(len(results), frames)
        self.assertEqual((sink.frames(), sink.frames_scored(), sink.frames_skipped()), (frames, frames, 0))
        azimuths = [r[K.azimuth_rad] for r in results]
        # The azimuth is the peak of Σ_t |aᴴy_t|²/‖a‖²: no azimuth on a fine grid around it is higher.
        y_e = (np.arange(self.k) - (self.k - 1) / 2.0) * 0.05
        for frame, az in zip(obs, azimuths):
            y = frame.reshape(self.k, -1)
            grid = np.linspace(-np.pi / 2, np.pi / 2, 4001)
            steer = np.exp(2j * np.pi * np.outer(np.sin(grid), y_e) / self.lam)
            power = np.sum(np.abs(steer.conj() @ y) ** 2, axis=1)
            at = np.sum(np.abs(np.exp(2j * np.pi * y_e * np.sin(az) / self.lam).conj() @ y) ** 2)
            self.assertGreaterEqual(at, power.max() * (1 - 1e-6))
        # The label and probabilities are the one-antenna sink's on those beamformed pilots.
        want = self.one_antenna(beamformed(obs, self.k, self.lam, azimuths))
        for r, w in zip(results, want):
            self.assertEqual(r[K.label], w[K.label])
            np.testing.assert_allclose(r[K.probs], w[K.probs], atol=2e-4)
        # At 20 dB per element the azimuth follows the target of interest's.
        errors = [abs(r[K.azimuth_rad] - r[K.truth][K.azimuth_rad]) for r in results]
        self.assertLess(np.median(errors), 0.01)
        self.assertEqual(sink.accuracy(), np.mean([r[K.correct] for r in results]))

    def test_a_track_bundle_decides_over_the_beamformed_frames(self):
        """The shipped track bundle on a body crossing the line of sight for its whole stream: one
        track, each frame's decision the one-antenna sink's over the same beamformed frames."""
        track = os.path.join(SOURCE, "models", "classifier_kinematic_track")
        self.assertEqual(sems.model_bundle.load(track).mask.positions(), self.mask.positions())
        frames = 24
        sink, results, obs = self.stream(frames, bundle=track, track_frames=64)
        self.assertTrue(sink.track_mode())
        self.assertEqual(sink.tracks_started(), 1)
        self.assertEqual([r[K.track_frames] for r in results], list(range(1, frames + 1)))
        azimuths = [r[K.azimuth_rad] for r in results]
        self.assertGreater(np.ptp([r[K.truth][K.azimuth_rad] for r in results]), 0.0)  # it crosses
        want = self.one_antenna(beamformed(obs, self.k, self.lam, azimuths), bundle=track)
        for r, w in zip(results, want):
            self.assertEqual(r[K.label], w[K.label])
            np.testing.assert_allclose(r[K.probs], w[K.probs], atol=2e-4)

    def test_array_mismatches_are_refused_by_name(self):
        with self.assertRaisesRegex(ValueError, "n_elements = 8 needs the array"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=8)
        with self.assertRaisesRegex(ValueError, "8 receive elements, but n_elements = 4"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=4, array=ARRAY)
        with self.assertRaisesRegex(ValueError, r"n_elements must be in \[1, 1024\], got 0"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=0, array=ARRAY)
        mimo = json.dumps({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 4, "spacing_m": 0.05}},
                           "transmit": {"ula": {"elements": 2, "spacing_m": 0.2}}})
        with self.assertRaisesRegex(ValueError, "2 transmit elements"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=4, array=mimo)
        with self.assertRaisesRegex(ValueError, "no_such_array"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=8, array="no_such_array")
        with self.assertRaisesRegex(ValueError, "array JSON text does not parse"):
            sems.classifier_sink(BUNDLE, self.n_p, n_elements=8, array="{nope")
        self.assertEqual(sems.classifier_sink(BUNDLE, self.n_p).n_elements(), 1)


if __name__ == "__main__":
    gr_unittest.run(qa_classifier_sink_array)
