#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: target_channel_td, the sample-level emulator, against the frequency-domain
model and the closed forms of ICI (pure Doppler) and ISI (delay past the prefix)."""
import json
import math

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

B = 30e6


def qpsk(rows, m, seed=1):
    rng = np.random.default_rng(seed)
    return ((rng.integers(0, 2, (rows, m)) * 2 - 1) + 1j * (rng.integers(0, 2, (rows, m)) * 2 - 1)).astype(
        np.complex64) / np.sqrt(2)


def scene_json(targets, fading="rayleigh"):
    """targets: (class, range_m, velocity_mps, [(excess_range_m, power)...], micro_doppler dict or None)"""
    out = []
    for cls, rng_m, v, paths, md in targets:
        t = {"class": cls, "range_m": rng_m, "velocity_mps": v, "power": 1,
             "paths": [{"excess_range_m": e, "power": p} for e, p in paths]}
        if md:
            t["micro_doppler"] = md
        out.append(t)
    return json.dumps({"format": "sems.scene", "version": 1, "fading": fading, "targets": out})


def frame_tags(frames, n, s=1):
    key = pmt.intern(sems.keys.frame_tag)
    return [gr.tag_utils.python_to_tag((f * n * s, key, pmt.from_uint64(f))) for f in range(frames)]


def ici_closed_form(eps, m):
    """1 - |S(eps)|^2: the share of a unit-power symbol leaked to the other subcarriers by a
    frequency offset of eps subcarrier spacings over an M-sample window (all subcarriers loaded)."""
    if eps == 0:
        return 0.0
    s = math.sin(math.pi * eps) / (m * math.sin(math.pi * eps / m))
    return 1.0 - s * s


class qa_target_channel_td(gr_unittest.TestCase):

    def fd(self, x, n, m, **kw):
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=m, tags=frame_tags(len(x) // n, n))
        ch = sems.target_channel(n_symbols=n, n_subcarriers=m, **kw)
        sink = blocks.vector_sink_c(m)
        tb = gr.top_block()
        tb.connect(src, ch, sink)
        tb.run()
        return np.array(sink.data()).reshape(-1, m), sink.tags()

    def td(self, x, n, m, cp, max_items=None, samples_sink=False, **kw):
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=m, tags=frame_tags(len(x) // n, n))
        tx = sems.ofdm_tx(m, cp)
        ch = sems.target_channel_td(n_symbols=n, n_subcarriers=m, cp_len=cp, **kw)
        if max_items:
            ch.set_max_noutput_items(max_items)
        rx = sems.ofdm_rx(m, cp)
        sink = blocks.vector_sink_c(m)
        tb = gr.top_block()
        tb.connect(src, tx, ch, rx, sink)
        raw = None
        if samples_sink:
            raw = blocks.vector_sink_c()
            tb.connect(ch, raw)
        tb.run()
        self.ch = ch
        y = np.array(sink.data()).reshape(-1, m)
        return (y, sink.tags(), np.array(raw.data()) if raw else None)

    def test_001_equals_frequency_domain_within_cp(self):
        # Fractional delays up to the prefix, several paths, Rayleigh gains, no Doppler:
        # the same seed gives the frequency-domain model's Y = H·X to float tolerance.
        n, m, cp, frames = 8, 64, 16, 4
        sc = scene_json([("car", 7.3, 0.0, [(0, 1), (12.4, 0.5), (50.1, 0.2)], None),
                         ("pedestrian", 41.7, 0.0, [(0, 1)], None)])
        x = qpsk(frames * n, m)
        y_fd, tags_fd = self.fd(x, n, m, scene=sc, seed=11)
        y_td, tags_td, _ = self.td(x, n, m, cp, scene=sc, seed=11)
        self.assertEqual(y_td.shape, y_fd.shape)
        nmse = np.sum(np.abs(y_td - y_fd) ** 2) / np.sum(np.abs(y_fd) ** 2)
        self.assertLess(nmse, 1e-11)
        np.testing.assert_allclose(y_td, y_fd, rtol=0, atol=2e-5)
        # the same truth on the same symbols
        def truths(tags):
            return [(t.offset, pmt.to_python(t.value)) for t in tags if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]
        self.assertEqual(truths(tags_td), truths(tags_fd))
        self.assertEqual(len(truths(tags_td)), frames)

    def test_002_fractional_delay_phase_slope(self):
        n, m, cp = 4, 64, 16
        for rng_m in (0.0, 2.5, 13.37, 79.0):
            with self.subTest(range_m=rng_m):
                sc = scene_json([("car", rng_m, 0.0, [(0, 1)], None)], fading="none")
                x = qpsk(n, m)
                y, tags, _ = self.td(x, n, m, cp, scene=sc)
                d = 2 * rng_m / 3e8 * B  # delay index
                h = (y / x)[1]
                expected = np.exp(-2j * np.pi * np.arange(m) * d / m)
                np.testing.assert_allclose(h, expected, rtol=0, atol=1e-5)
                slope = np.polyfit(np.arange(m), np.unwrap(np.angle(h)), 1)[0]
                self.assertAlmostEqual(-slope * m / (2 * np.pi), d, places=4)

    def test_003_doppler_ici_matches_closed_form(self):
        # A contiguous OFDM stream (T = (M+CP)/B) at 300 GHz: a pure Doppler shift of eps
        # subcarrier spacings. ICI = power left after removing each symbol's common
        # coefficient, against 1 - |sin(pi eps)/(M sin(pi eps/M))|^2, within 10 %.
        n, m, cp = 64, 64, 16
        s = m + cp
        lam = 3e8 / 300e9
        for eps in (0.05, 0.15, 0.3):
            with self.subTest(eps=eps):
                nu = eps * B / m
                v = nu * lam / 2
                sc = scene_json([("car", 0.0, v, [(0, 1)], None)], fading="none")
                x = qpsk(n, m, seed=3)
                y, _, _ = self.td(x, n, m, cp, scene=sc, carrier_hz=300e9, symbol_interval_s=s / B)
                c = np.sum(y * np.conj(x), axis=1, keepdims=True) / np.sum(np.abs(x) ** 2, axis=1, keepdims=True)
                ici = np.mean(np.abs(y - c * x) ** 2) / np.mean(np.abs(y) ** 2)
                expected = ici_closed_form(eps, m)
                self.assertLess(abs(ici / expected - 1), 0.10, f"ICI {ici:.4e} vs closed form {expected:.4e}")
                # The desired coefficient of symbol n is S(eps) at the phase of the FFT window's
                # centre, 2π ν (n T + (CP + (M-1)/2)/B): the time convention (sample k of symbol
                # n at n T + k/B). Per symbol the data's ICI adds a zero-mean error of power
                # ~ICI/M; over N symbols the mean is within 4 sigma of S.
                mag = math.sin(math.pi * eps) / (m * math.sin(math.pi * eps / m))
                t = np.arange(n) * s / B + (cp + (m - 1) / 2) / B
                g = np.mean(c[:, 0] * np.exp(-2j * np.pi * nu * t))
                tol = 4 * math.sqrt(expected / (m * n))
                self.assertAlmostEqual(g.real, mag, delta=tol)
                self.assertAlmostEqual(g.imag, 0.0, delta=tol)

    def test_004_isi_past_the_prefix(self):
        # Delay D = CP + e samples, no Doppler, no fading: the coefficient is (M-e)/M and the
        # interference (ISI from the previous symbol + ICI from the cut window) e(2M-e)/M^2.
        n, m, cp = 200, 64, 16
        for e in (1, 4, 12, 30):
            with self.subTest(excess=e):
                d = cp + e
                sc = scene_json([("car", d * 5.0, 0.0, [(0, 1)], None)], fading="none")
                x = qpsk(n, m, seed=5)
                y, _, _ = self.td(x, n, m, cp, scene=sc)
                h = np.exp(-2j * np.pi * np.arange(m) * d / m)
                g = y[1:] / h  # skip symbol 0 (silence before the stream)
                xx = x[1:]
                c = np.sum(g * np.conj(xx)) / np.sum(np.abs(xx) ** 2)
                interference = np.mean(np.abs(g - c * xx) ** 2)
                expected = e * (2 * m - e) / m ** 2
                # c's error from the random data's interference: 4 sigma
                tol = 4 * math.sqrt(expected / xx.size)
                self.assertAlmostEqual(c.real, (m - e) / m, delta=tol)
                self.assertAlmostEqual(c.imag, 0.0, delta=tol)
                self.assertLess(abs(interference / expected - 1), 0.10,
                                f"interference {interference:.4e} vs closed form {expected:.4e}")
                # without ISI the frequency-domain model would say c = 1, no interference:
                # the NMSE of the FD model is 2e/M (its closed form)
                nmse = np.mean(np.abs(g - xx) ** 2)
                self.assertLess(abs(nmse / (2 * e / m) - 1), 0.10)

    def test_004b_micro_doppler_phase_is_the_models(self):
        # Drones and a pedestrian with micro-Doppler inside the prefix, the defaults: the
        # sample-level phase agrees with the frequency-domain model up to the model's own
        # error, below the closed-form bound at the peak Doppler (2 - 2|S|cos ψ ~ 1.4e-5 for
        # 351 Hz); a wrong micro-Doppler phase (sign, scale, time) would give NMSE ~ 1.
        n, m, cp, frames = 32, 64, 16, 3
        sc = scene_json([("drone", 30.0, 10.0, [(0, 1)], {"rate_hz": 120, "amplitude_m": 0.01, "phase_rad": 0.4}),
                         ("pedestrian", 60.0, 2.0, [(0, 1)], {"rate_hz": 3, "amplitude_m": 0.1, "phase_rad": 1.0})])
        x = qpsk(frames * n, m, seed=6)
        y_fd, _ = self.fd(x, n, m, scene=sc, seed=2)
        y_td, _, _ = self.td(x, n, m, cp, scene=sc, seed=2)
        nmse = np.sum(np.abs(y_td - y_fd) ** 2) / np.sum(np.abs(y_fd) ** 2)
        self.assertLess(nmse, 1.4e-5)
        self.assertGreater(nmse, 1e-9)  # the per-sample phase is there (ICI, window-centre phase)

    def test_005_any_work_size(self):
        n, m, cp = 4, 16, 4
        sc = scene_json([("drone", 30.0, 7.0, [(0, 1), (10.3, 0.5)], {"rate_hz": 100, "amplitude_m": 0.01,
                                                                       "phase_rad": 0.3})])
        x = qpsk(5 * n, m, seed=9)
        kw = dict(scene=sc, seed=4, snr_db=10.0, bandwidth_hz=m * 468.75e3)
        ref, ref_tags, ref_raw = self.td(x, n, m, cp, samples_sink=True, **kw)
        for items in (m + cp, 3 * (m + cp), 7 * (m + cp)):
            with self.subTest(max_noutput_items=items):
                y, tags, raw = self.td(x, n, m, cp, max_items=items, samples_sink=True, **kw)
                np.testing.assert_array_equal(raw, ref_raw)
                self.assertEqual(len(tags), len(ref_tags))

    def test_006_noise_is_per_resource_element(self):
        n, m, cp = 32, 64, 16
        x = np.zeros((4 * n, m), dtype=np.complex64)
        for snr in (0.0, 10.0):
            y, tags, raw = self.td(x, n, m, cp, samples_sink=True, snr_db=snr, seed=2)
            var = 10 ** (-snr / 10)
            self.assertAlmostEqual(np.mean(np.abs(raw) ** 2) / var, 1.0, delta=0.03)
            self.assertAlmostEqual(np.mean(np.abs(y) ** 2) / var, 1.0, delta=0.03)
            snrs = [pmt.to_python(t.value)[sems.keys.snr_db] for t in tags
                    if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]
            self.assertEqual(snrs, [snr] * 4)

    def test_007_tags_and_counters(self):
        n, m, cp = 4, 16, 4
        s = m + cp
        x = np.ones(3 * n * s, dtype=np.complex64)
        key = pmt.intern(sems.keys.frame_tag)
        tags = [gr.tag_utils.python_to_tag((0, key, pmt.from_uint64(5))),
                gr.tag_utils.python_to_tag((n * s + 3, key, pmt.from_uint64(9))),  # off the symbol grid
                gr.tag_utils.python_to_tag((2 * n * s, key, pmt.from_uint64(7)))]
        x[s + 2] = np.nan
        src = blocks.vector_source_c(x.tolist(), tags=tags)
        ch = sems.target_channel_td(n_symbols=n, n_subcarriers=m, cp_len=cp, bandwidth_hz=m * 468.75e3)
        sink = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(src, ch, sink)
        tb.run()
        truth = [(t.offset, pmt.to_python(t.value)[sems.keys.frame]) for t in sink.tags()
                 if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]
        self.assertEqual(truth, [(0, 5), (n * s, 6), (2 * n * s, 7)])
        frames = [(t.offset, pmt.to_uint64(t.value)) for t in sink.tags() if pmt.eqv(t.key, key)]
        self.assertEqual(frames, [(0, 5), (n * s + 3, 9), (2 * n * s, 7)])  # passed on as they came
        self.assertEqual(ch.frames(), 3)
        self.assertEqual(ch.misaligned_tags(), 1)
        self.assertEqual(ch.nonfinite_symbols(), 1)

    def test_007b_other_cyclic_prefix_refused(self):
        # ofdm_tx with CP 16, the channel with CP 48: the frame tags are 32·80 samples apart,
        # not 32·112. The channel stops the stream and names both prefixes.
        n, m = 32, 64
        x = qpsk(4 * n, m)
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=m, tags=frame_tags(4, n))
        ch = sems.target_channel_td(cp_len=48)
        sink = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(src, sems.ofdm_tx(m, 16), ch, sink)
        tb.run()  # returns: the stream is stopped, not hung
        err = ch.stream_error()
        self.assertIn("transmitter's cyclic prefix is 16 samples, this block's cp_len is 48", err)
        self.assertIn("2560 samples after frame 0", err)
        self.assertLess(len(sink.data()), 4 * n * (m + 48))
        # The same chain with one prefix runs to the end without an error.
        ch = sems.target_channel_td(cp_len=16)
        sink = blocks.vector_sink_c()
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=m, tags=frame_tags(4, n))
        tb = gr.top_block()
        tb.connect(src, sems.ofdm_tx(m, 16), ch, sink)
        tb.run()
        self.assertEqual(ch.stream_error(), "")
        self.assertEqual(len(sink.data()), 4 * n * (m + 16))

    def test_008_live_snr_setter(self):
        ch = sems.target_channel_td()
        ch.set_snr_db(7.0)
        self.assertEqual(ch.snr_db(), 7.0)
        with self.assertRaisesRegex(ValueError, "target_channel_td: snr_db"):
            ch.set_snr_db(float("nan"))

    def test_009_bad_parameters(self):
        cases = [
            (dict(cp_len=-1), "cp_len"),
            (dict(symbol_interval_s=1e-6), "symbol_interval_s"),  # shorter than (64+16)/30 MHz
            (dict(snr_db=float("-inf")), "snr_db"),
            (dict(n_subcarriers=0), "n_subcarriers"),
            (dict(classes=["boat"]), "boat"),
            (dict(scene=scene_json([("car", 400.0, 0.0, [(0, 1)], None)])), "unambiguous range"),
        ]
        for kw, needle in cases:
            with self.subTest(**{k: str(v)[:20] for k, v in kw.items()}):
                with self.assertRaisesRegex(ValueError, "target_channel_td.*" + needle):
                    sems.target_channel_td(**kw)

    def test_010_random_scene_array(self):
        # The Array and azimuth interval parameters give the streams of the random scene file that
        # states them ("array", "random.azimuth_rad"), bit for bit; ula4_5g: 4 receive, 1 transmit.
        n, m, cp, frames, n_rx = 4, 16, 4, 8, 4
        x = qpsk(frames * n, m + cp).ravel()
        common = dict(n_symbols=n, n_subcarriers=m, cp_len=cp, bandwidth_hz=m * 468.75e3, snr_db=20.0, seed=3,
                      n_receive=n_rx)

        def streams(**kw):
            ch = sems.target_channel_td(**common, **kw)
            sinks = [blocks.vector_sink_c() for _ in range(n_rx)]
            tb = gr.top_block()
            tb.connect(blocks.vector_source_c(x.tolist()), ch)
            for k, sink in enumerate(sinks):
                tb.connect((ch, k), sink)
            tb.run()
            return ([np.array(sink.data()) for sink in sinks],
                    [[pmt.to_python(t.value) for t in sink.tags() if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]
                     for sink in sinks])

        ys, truths = streams(classes=["car"], array="ula4_5g", azimuth_min_rad=-0.5, azimuth_max_rad=0.5)
        azimuths = [d[sems.keys.azimuth_rad] for d in truths[0]]
        self.assertEqual(len(azimuths), frames)
        self.assertTrue(all(-0.5 <= a <= 0.5 for a in azimuths), azimuths)
        self.assertGreater(len(set(azimuths)), 1)
        text = json.dumps({"format": "sems.scene", "version": 1, "array": "ula4_5g",
                           "random": {"classes": ["car"], "azimuth_rad": [-0.5, 0.5]}})
        want, want_truths = streams(scene=text)
        for k in range(n_rx):
            self.assertEqual(len(ys[k]), len(x))
            np.testing.assert_array_equal(ys[k], want[k], f"output {k}")
            self.assertEqual(truths[k], want_truths[k], f"output {k}")

    def test_011_array_parameters_refused(self):
        fixed = scene_json([("car", 50.0, 0.0, [(0, 1)], None)])
        cases = [
            (dict(scene=fixed, array="ula4_5g", n_receive=4), "array, azimuth_min_rad and azimuth_max_rad describe "
                                                              "random scenes"),
            (dict(azimuth_min_rad=-0.5, azimuth_max_rad=0.5), "azimuth_min_rad = -0.5 and azimuth_max_rad = 0.5 "
                                                              "set the targets' directions, which change nothing "
                                                              "without an array"),
            (dict(array="ula4_5g", n_receive=4, azimuth_min_rad=0.5, azimuth_max_rad=-0.5),
             "azimuth_min_rad = 0.5 exceeds azimuth_max_rad = -0.5"),
            (dict(array="ula4_5g", n_receive=4, azimuth_max_rad=4.0), r"azimuth_max_rad must lie in \[-pi, pi\]"),
            (dict(array="no_such_array"), "array: array \"no_such_array\": no such file"),
            (dict(array="ula4_5g"), "the scene's array has 4 receive x 1 transmit elements, but n_receive = 1 and "
                                    "n_transmit = 1"),
        ]
        for kw, needle in cases:
            with self.subTest(**{k: str(v)[:20] for k, v in kw.items()}):
                with self.assertRaisesRegex(ValueError, "target_channel_td: .*" + needle):
                    sems.target_channel_td(**kw)


if __name__ == "__main__":
    gr_unittest.run(qa_target_channel_td)
