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
            self.assertEqual(json.load(open(path))["format"], "sems.array")
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
        sc = sems.scene.fixed([t], fading=sems.fading_kind.none).with_array(a)
        cm = sems.channel_model(fs, sc, 1)
        r = cm.draw(0)
        self.assertEqual(cm.n_elements(), 4)
        self.assertAlmostEqual(r.paths[0].azimuth_rad, -0.6)
        h0 = cm.channel(r, 0)  # the origin's channel
        u_y = math.sin(-0.6)
        m = np.arange(fs.n_subcarriers)
        for k, p in enumerate(a.receive()):
            along = u_y * p[1]
            want = h0 * np.exp(2j * np.pi * along / fs.wavelength_m()) * \
                np.exp(2j * np.pi * m * fs.subcarrier_spacing_hz() * along / 3e8)
            np.testing.assert_allclose(cm.channel(r, 0, k), want, atol=1e-5)
        with self.assertRaisesRegex(ValueError, "element 4"):
            cm.channel(r, 0, 4)


if __name__ == "__main__":
    gr_unittest.run(qa_array)
