#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Arrays from Python: the file, the steering vector against the ULA's textbook phase, and each
element's channel from a scene with an array against the plane wave written out here."""
import json
import math
import os
import tempfile

import numpy as np
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
        self.assertGreater(sems.angle_crb_rad2(a, -0.6, 0.0, fs.wavelength_m(), 1e3), 0.0)
        with self.assertRaisesRegex(ValueError, "8 elements x snapshots"):
            bf.estimate(y[:4])

    def test_one_stream_blocks_refuse_an_array_scene(self):
        text = json.dumps({"format": "sems.scene", "version": 1,
                           "array": {"receive": {"ula": {"elements": 4, "spacing_m": 0.05}}},
                           "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8}]})
        for block in (sems.target_channel, sems.target_channel_td):
            with self.assertRaisesRegex(ValueError, "4 receive x 1 transmit elements.*1 output stream"):
                block(scene=text)


if __name__ == "__main__":
    gr_unittest.run(qa_array)
