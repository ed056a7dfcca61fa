#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Arrays from Python: the file, the steering vector against the ULA's textbook phase, and each
element's channel from a scene with an array against the plane wave written out here."""
import json
import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import gr_unittest, sems


class qa_array(gr_unittest.TestCase):

    def test_ula_file_round_trip_and_errors(self):
        a = sems.array_geometry.ula(8, 0.05)
        self.assertEqual((a.n_receive(), a.n_transmit()), (8, 1))
        self.assertAlmostEqual(a.receive()[0][1], -0.175)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "ula.json")
            a.save(path)
            with open(path) as f:
                self.assertEqual(json.load(f)["format"], "sems.array")
            self.assertTrue(sems.array_geometry.load(path) == a)
        # A MIMO array's streams: receive element k with transmit element j at p_k + q_j, k-major.
        mimo = sems.array_geometry.from_positions([(0, -0.05, 0), (0, 0.05, 0)], [(0, 0, 0), (0, 0.2, 0)])
        np.testing.assert_allclose(np.array(mimo.virtual_offsets()),
                                   [(0, -0.05, 0), (0, 0.15, 0), (0, 0.05, 0), (0, 0.25, 0)], atol=1e-15)
        with self.assertRaisesRegex(ValueError, "spacing_m"):
            sems.array_geometry.ula(4, 0.0)
        with self.assertRaisesRegex(ValueError, "coincide"):
            sems.array_geometry.from_positions([(0, 0, 0), (0, 0, 0)])

    def test_steering_vector_is_the_ula_phase(self):
        a = sems.array_geometry.ula(8, 0.05)
        az = 0.4
        s = np.array(sems.steering_vector(a, az, 0.0, 0.1))
        y = (np.arange(8) - 3.5) * 0.05
        np.testing.assert_allclose(s, np.exp(2j * np.pi / 0.1 * y * math.sin(az)), atol=1e-12)

    def test_each_element_sees_the_plane_wave(self):
        fs = sems.frame_settings()
        a = sems.array_geometry.ula(4, 0.05)
        t = sems.target_spec(sems.target_class.car, 60.0, 8.0, azimuth_rad=-0.6)
        one = sems.scene.fixed([t], fading=sems.fading_kind.none)
        cm = sems.channel_model(fs, one.with_array(a), 1)
        r = cm.draw(0)
        self.assertEqual(cm.n_elements(), 4)
        self.assertAlmostEqual(r.paths[0].azimuth_rad, -0.6)
        single = sems.channel_model(fs, one, 1)  # the origin's channel: the same target, one antenna
        h0 = single.channel(single.draw(0), 0)
        with self.assertRaisesRegex(ValueError, "4 streams"):
            cm.channel(r, 0)  # an array's channel is asked for by element
        u_y = math.sin(-0.6)
        m = np.arange(fs.n_subcarriers)
        for k, p in enumerate(a.receive()):
            along = u_y * p[1]
            want = h0 * np.exp(2j * np.pi * along / fs.wavelength_m()) * \
                np.exp(2j * np.pi * m * fs.subcarrier_spacing_hz() * along / 3e8)
            np.testing.assert_allclose(cm.channel(r, 0, k), want, atol=1e-5)
        with self.assertRaisesRegex(ValueError, "element 4"):
            cm.channel(r, 0, 4)

    def test_beamforming_finds_the_emulated_target(self):
        # The emulator's array channel and the angle baselines share one steering function: a
        # noiseless target at -0.6 rad, its grid's resource elements as snapshots, is found there.
        fs = sems.frame_settings()
        a = sems.array_geometry.ula(8, 0.05)
        t = sems.target_spec(sems.target_class.car, 60.0, 8.0, azimuth_rad=-0.6)
        cm = sems.channel_model(fs, sems.scene.fixed([t]).with_array(a), 3)
        r = cm.draw(0)
        y = np.stack([cm.channel(r, 0, k)[:, :4].ravel() for k in range(8)])  # 8 x 128 snapshots
        bf = sems.beamforming_angle_estimator(a, 0.0, fs.wavelength_m())
        self.assertAlmostEqual(bf.estimate(y)[0], -0.6, delta=2e-3)  # the band's delay spread: < 1e-3 rad
        music = sems.music_angle_estimator(a, 0.0, fs.wavelength_m(), 1)
        self.assertAlmostEqual(music.estimate(y)[0], -0.6, delta=2e-3)
        capon = sems.capon_angle_estimator(a, 0.0, fs.wavelength_m())
        self.assertAlmostEqual(capon.estimate(y)[0], -0.6, delta=2e-3)
        self.assertGreater(sems.angle_crb_rad2(a, -0.6, 0.0, fs.wavelength_m(), 1e3), 0.0)
        with self.assertRaisesRegex(ValueError, "8 elements x snapshots"):
            bf.estimate(y[:4])

    def test_stream_counts_must_match_the_array(self):
        text = json.dumps({"format": "sems.scene", "version": 1,
                           "array": {"receive": {"ula": {"elements": 4, "spacing_m": 0.05}}},
                           "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8}]})
        for block in (sems.target_channel, sems.target_channel_td):
            with self.assertRaisesRegex(ValueError, "4 receive x 1 transmit elements, but n_receive = 1 and n_transmit = 1"):
                block(scene=text)
            self.assertEqual(block(scene=text, n_receive=4).output_signature().max_streams(), 4)
        with self.assertRaisesRegex(ValueError, "1 receive x 1 transmit elements, but n_receive = 3"):
            sems.target_channel(n_receive=3)  # a random scene has no array
        with self.assertRaisesRegex(ValueError, "n_transmit must be in"):
            sems.target_channel(scene=text, n_receive=4, n_transmit=0)
        self.assertEqual(sems.target_channel(scene=text, n_receive=4).output_signature().max_streams(), 4)

    def test_each_receive_output_sums_its_transmit_inputs(self):
        # 2 receive x 2 transmit elements, noiseless: output k is Σ_j H_{k,j} ⊙ x_j, H_{k,j} the
        # model's stream k·2 + j; every output carries the frame's truth.
        from gnuradio import blocks, gr
        fs = sems.frame_settings()
        array = {"receive": {"positions_m": [[0, -0.025, 0], [0, 0.025, 0]]},
                 "transmit": {"positions_m": [[0, 0, 0], [0, 0.1, 0]]}}
        scene = {"format": "sems.scene", "version": 1, "array": array,
                 "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8, "azimuth_rad": 0.4}]}
        text = json.dumps(scene)
        rng = np.random.default_rng(3)
        n, m = fs.n_symbols, fs.n_subcarriers
        x = [(rng.standard_normal(n * m) + 1j * rng.standard_normal(n * m)).astype(np.complex64) for _ in range(2)]
        tb = gr.top_block()
        ch = sems.target_channel(scene=text, seed=7, n_receive=2, n_transmit=2)
        sinks = [blocks.vector_sink_c(m) for _ in range(2)]
        for j in range(2):
            tb.connect(blocks.vector_source_c(x[j].tolist(), False, m), (ch, j))
        for k in range(2):
            tb.connect((ch, k), sinks[k])
        tb.run()
        cm = sems.channel_model(fs, sems.scene.parse(text), 7)
        r = cm.draw(0)
        for k in range(2):
            want = sum(np.asarray(cm.channel(r, 0, 2 * k + j)).reshape(-1) * x[j] for j in range(2))
            np.testing.assert_allclose(np.asarray(sinks[k].data()), want, atol=2e-5)
            tags = [t for t in sinks[k].tags() if str(t.key) == "sems_truth"]
            self.assertEqual([t.offset for t in tags], [0])
            truth = pmt.to_python(tags[0].value)  # with an array: the target's direction
            self.assertEqual((truth[sems.keys.azimuth_rad], truth[sems.keys.elevation_rad]), (0.4, 0.0))
        self.assertEqual((r.truth[sems.keys.azimuth_rad], r.truth[sems.keys.elevation_rad]), (0.4, 0.0))
        # Without an array a direction changes nothing, and neither the tag nor the truth has one.
        del scene["array"]
        one = sems.channel_model(fs, sems.scene.parse(json.dumps(scene)), 7).draw(0).truth
        self.assertNotIn(sems.keys.azimuth_rad, one)
        self.assertNotIn(sems.keys.elevation_rad, one)
        tb = gr.top_block()
        single = blocks.vector_sink_c(m)
        tb.connect(blocks.vector_source_c(x[0].tolist(), False, m), sems.target_channel(scene=json.dumps(scene)), single)
        tb.run()
        truth = pmt.to_python([t for t in single.tags() if str(t.key) == "sems_truth"][0].value)
        self.assertNotIn(sems.keys.azimuth_rad, truth)
        self.assertEqual(truth[sems.keys.class_name], "car")

    def test_time_domain_outputs_are_each_elements_channel(self):
        # The sample-level emulator with 3 receive elements, noiseless, a still target inside the
        # prefix: each output's prefix-free window, transformed, is that element's H times the
        # transmitted window's spectrum (the frequency-domain model at the element).
        from gnuradio import blocks, gr
        fs = sems.frame_settings()
        n, m, cp = fs.n_symbols, fs.n_subcarriers, fs.cp_len
        scene = {"format": "sems.scene", "version": 1, "fading": "none",
                 "array": {"receive": {"ula": {"elements": 3, "spacing_m": 0.1}}},
                 "targets": [{"class": "car", "range_m": 33, "velocity_mps": 0, "azimuth_rad": 0.7}]}
        text = json.dumps(scene)
        rng = np.random.default_rng(4)
        x = (rng.standard_normal(n * (m + cp)) + 1j * rng.standard_normal(n * (m + cp))).astype(np.complex64)
        tb = gr.top_block()
        ch = sems.target_channel_td(scene=text, seed=3, n_receive=3)
        sinks = [blocks.vector_sink_c() for _ in range(3)]
        tb.connect(blocks.vector_source_c(x.tolist(), False), ch)
        for k in range(3):
            tb.connect((ch, k), sinks[k])
        tb.run()
        cm = sems.channel_model(fs, sems.scene.parse(text), 3)
        r = cm.draw(0)
        for k in range(3):
            h = np.asarray(cm.channel(r, 0, k))
            y = np.asarray(sinks[k].data())
            for s in (1, 17, 31):  # symbols whose previous symbol is in the stream
                win = slice(s * (m + cp) + cp, (s + 1) * (m + cp))
                want = h[s] * np.fft.fft(x[win])
                np.testing.assert_allclose(np.fft.fft(y[win]), want, atol=2e-4 * np.abs(want).max())

    def test_extractor_reads_every_element_at_the_pilots(self):
        # A 3-element ULA's streams into one extractor: per frame, element-major, element k's
        # pilots equal its channel there (noiseless, x = 1); two frames, each with its truth.
        from gnuradio import blocks, gr
        fs = sems.frame_settings()
        n, m = fs.n_symbols, fs.n_subcarriers
        scene = {"format": "sems.scene", "version": 1,
                 "array": {"receive": {"ula": {"elements": 3, "spacing_m": 0.05}}},
                 "targets": [{"class": "car", "range_m": 45, "velocity_mps": -6, "azimuth_rad": -0.3}]}
        text = json.dumps(scene)
        positions = [3, 70, 64 * 5 + 11, 64 * 31 + 63]
        tb = gr.top_block()
        src = blocks.vector_source_c([1 + 0j] * (2 * n * m), False, m)
        ch = sems.target_channel(scene=text, seed=2, n_receive=3)
        ex = sems.pilot_extractor(pilot_positions=positions, n_elements=3)
        sink = blocks.vector_sink_c(3 * len(positions))
        tb.connect(src, ch)
        for k in range(3):
            tb.connect((ch, k), (ex, k))
        tb.connect(ex, sink)
        tb.run()
        self.assertEqual((ex.n_elements(), ex.n_pilots(), ex.frames_out()), (3, 4, 2))
        got = np.asarray(sink.data()).reshape(2, 3, len(positions))
        cm = sems.channel_model(fs, sems.scene.parse(text), 2)
        for f in range(2):
            r = cm.draw(f)
            for k in range(3):
                h = np.asarray(cm.channel(r, f * n, k)).reshape(-1)
                np.testing.assert_allclose(got[f, k], h[positions], atol=1e-5)
        self.assertEqual(len([t for t in sink.tags() if str(t.key) == "sems_truth"]), 2)
        with self.assertRaisesRegex(ValueError, "n_elements must be in"):
            sems.pilot_extractor(pilot_positions=positions, n_elements=0)


if __name__ == "__main__":
    gr_unittest.run(qa_array)
