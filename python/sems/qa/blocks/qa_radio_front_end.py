#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""SemS Radio Front End and SemS Phase Noise Source against their closed forms: the oscillator's
spectrum, the phase error of a delayed path under a shared oscillator, IQ image rejection, the
converter's SQNR, the leakage's power and alignment, the ideal radio being the channel alone, an
array's elements with one oscillator or their own."""
import json
import math
import os

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest

from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..", ".."))
RADIOS = os.path.join(SOURCE, "examples", "radios")
FS = sems.frame_settings().bandwidth_hz
N, M, CP = 32, 64, 16
S = M + CP


def still_target(range_m):
    """One non-fading, motionless path of unit power at range_m (delay index range_m / 5 m)."""
    return json.dumps({"format": "sems.scene", "version": 1, "fading": "none",
                       "targets": [{"class": "car", "range_m": range_m, "velocity_mps": 0.0, "power": 1,
                                    "paths": [{"excess_range_m": 0, "power": 1}]}]})


def ofdm(frames, seed=1):
    """Unit-power CP-OFDM samples (QPSK on every subcarrier, unitary IFFT)."""
    rng = np.random.default_rng(seed)
    sym = ((rng.integers(0, 2, (frames * N, M)) * 2 - 1) + 1j * (rng.integers(0, 2, (frames * N, M)) * 2 - 1))
    t = np.fft.ifft(sym / np.sqrt(2), axis=1) * np.sqrt(M)
    return np.concatenate([t[:, -CP:], t], axis=1).ravel().astype(np.complex64)


def frame_tags(frames):
    key = pmt.intern(sems.keys.frame_tag)
    return [gr.tag_utils.python_to_tag((f * N * S, key, pmt.from_uint64(f))) for f in range(frames)]


def run(block, x, tags=()):
    src = blocks.vector_source_c(x.tolist(), False, 1, list(tags))
    sink = blocks.vector_sink_c()
    tb = gr.top_block()
    tb.connect(src, block, sink)
    tb.run()
    return np.array(sink.data(), dtype=np.complex64), sink.tags()


def channel(**kw):
    return sems.target_channel_td(n_symbols=N, n_subcarriers=M, cp_len=CP, **kw)


def front_end(radio="", **kw):
    return sems.radio_front_end(radio, n_symbols=N, n_subcarriers=M, cp_len=CP, **kw)


def array_target(range_m, elements=4, azimuth_rad=0.3):
    """still_target seen by a ULA of `elements` elements 5 cm apart, from azimuth_rad."""
    scene = json.loads(still_target(range_m))
    scene["array"] = {"receive": {"ula": {"elements": elements, "spacing_m": 0.05}}}
    scene["targets"][0]["azimuth_rad"] = azimuth_rad
    return json.dumps(scene)


def run_elements(block, x, n):
    """Each of the block's n outputs for the input x."""
    src = blocks.vector_source_c(x.tolist(), False)
    sinks = [blocks.vector_sink_c() for _ in range(n)]
    tb = gr.top_block()
    tb.connect(src, block)
    for k, sink in enumerate(sinks):
        tb.connect((block, k), sink)
    tb.run()
    return [np.array(sink.data(), dtype=np.complex64) for sink in sinks]


def gaussian(n, seed=5):
    rng = np.random.default_rng(seed)
    return ((rng.standard_normal(n) + 1j * rng.standard_normal(n)) / np.sqrt(2)).astype(np.complex64)


def qfunc(k):
    return 0.5 * math.erfc(k / math.sqrt(2))


def sqnr_closed_form_db(enob, k):
    """SQNR of a complex Gaussian whose rails clip at k times their rms: granular noise of steps
    2A/2^b (A = k sigma) over sigma^2, k^2 / (3 4^b), plus the clipping error of each rail,
    E[(|x| - A)^2; |x| > A] / sigma^2 = 2 [(1 + k^2) Q(k) - k phi(k)]."""
    granular = k * k / (3.0 * 4.0 ** enob)
    clipping = 2.0 * ((1.0 + k * k) * qfunc(k) - k * math.exp(-k * k / 2) / math.sqrt(2 * math.pi))
    return -10.0 * math.log10(granular + clipping)


class qa_radio_front_end(gr_unittest.TestCase):

    def test_phase_noise_psd_matches_datasheet(self):
        """The oscillator's Welch PSD at three offsets within 1 dB of L(f) = D / (4 pi^2 f^2)."""
        dbc, f0, seg, nseg = -90.0, 100e3, 16384, 256
        src = sems.phase_noise_source(FS, dbc, f0, 1)
        head = blocks.head(gr.sizeof_gr_complex, seg * nseg)
        sink = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(src, head, sink)
        tb.run()
        z = np.array(sink.data()).reshape(nseg, seg)
        w = np.hanning(seg)
        psd = np.mean(np.abs(np.fft.fft(z * w, axis=1)) ** 2, axis=0) / (FS * np.sum(w * w))
        f = np.fft.fftfreq(seg, 1 / FS)
        d = sems.phase_diffusion_from_dbc(dbc, f0)
        self.assertAlmostEqual(d, src.diffusion(), delta=1e-9 * d)
        for offset in (20e3, 200e3, 2e6):
            band = (np.abs(np.abs(f) - offset) <= 0.1 * offset) & (f != 0)
            want = d / (4 * math.pi ** 2 * f[band] ** 2)
            err_db = 10 * math.log10(np.mean(psd[band] / want))
            self.assertLess(abs(err_db), 1.0, f"PSD at {offset:g} Hz off by {err_db:.2f} dB")

    def test_shared_oscillator_delay_sees_wiener_increment(self):
        """Monostatic: the echo at delay D samples is the clean echo times exp(j(phi[n-D] - phi[n])),
        phi the TX oscillator's phase; that error has variance D * D_phi / fs, and 0 at D = 0."""
        frames, seed, dbc = 100, 3, -80.0
        x = ofdm(frames)
        d_phi = sems.phase_diffusion_from_dbc(dbc, 100e3)
        for delay in (0, 20):
            scene = still_target(5.0 * delay)
            clean, _ = run(channel(scene=scene, seed=seed), x)
            fe = front_end(scene=scene, seed=seed, phase_noise_dbc_hz=dbc)
            noisy, _ = run(fe, x)
            # The same oscillator, regenerated: the echo is the clean one times exp(j(phi[n - D] - phi[n])).
            phi = sems.phase_noise_process(d_phi, FS, fe.oscillator_seeds[0]).phases(len(x))
            want = phi[:len(x) - delay] - phi[delay:]
            rms = np.sqrt(np.mean(np.abs(clean) ** 2))
            self.assertLess(np.max(np.abs(noisy[delay:] - clean[delay:] * np.exp(1j * want))), 1e-5 * rms)
            if delay == 0:
                self.assertLess(np.max(np.abs(noisy - clean)), 1e-5 * rms)
            else:
                independent = want[::delay]  # increments over disjoint windows
                var = np.mean(independent ** 2)
                closed = delay * d_phi / FS
                self.assertAlmostEqual(var / closed, 1.0, delta=0.05)

    def test_array_elements_share_or_own_their_oscillators(self):
        """An array's elements: under the ideal radio each output is the channel's element, bit for
        bit; with one shared oscillator every element's echo carries the same phase error
        phi[n - D] - phi[n]; with their own, element k's is phi[n - D] - phi_k[n], phi_k its own
        regenerated oscillator (element 0's the receiver's), independent of the others'."""
        frames, seed, dbc, delay, n_rx = 20, 3, -80.0, 20, 4
        x = ofdm(frames)
        scene = array_target(5.0 * delay, n_rx)
        clean = run_elements(channel(scene=scene, seed=seed, n_receive=n_rx), x, n_rx)
        for got, want in zip(run_elements(front_end(scene=scene, seed=seed, n_receive=n_rx), x, n_rx), clean):
            np.testing.assert_array_equal(got, want)
        # The phase errors sample by sample: from broadside, where every element's delay is the
        # whole D samples (a fractional delay is filtered per symbol, which spreads the phase
        # noise inside the symbol).
        scene = array_target(5.0 * delay, n_rx, azimuth_rad=0.0)
        clean = run_elements(channel(scene=scene, seed=seed, n_receive=n_rx), x, n_rx)
        d_phi = sems.phase_diffusion_from_dbc(dbc, 100e3)
        shared = front_end(scene=scene, seed=seed, n_receive=n_rx, phase_noise_dbc_hz=dbc)
        own = front_end(scene=scene, seed=seed, n_receive=n_rx, phase_noise_dbc_hz=dbc, element_oscillators="own")
        self.assertEqual(shared.element_oscillator_seeds, [shared.oscillator_seeds[0]] * n_rx)
        self.assertEqual(own.element_oscillator_seeds[0], shared.oscillator_seeds[0])
        self.assertEqual(len(set(own.element_oscillator_seeds)), n_rx)
        y_shared, y_own = run_elements(shared, x, n_rx), run_elements(own, x, n_rx)
        phases = [sems.phase_noise_process(d_phi, FS, s).phases(len(x)) for s in own.element_oscillator_seeds]
        phi = phases[0]  # the transmitter's, and the receiver's (monostatic)
        for k in range(n_rx):
            rms = np.sqrt(np.mean(np.abs(clean[k]) ** 2))
            want = phi[:len(x) - delay] - phi[delay:]
            self.assertLess(np.max(np.abs(y_shared[k][delay:] - clean[k][delay:] * np.exp(1j * want))), 1e-5 * rms, k)
            want = phi[:len(x) - delay] - phases[k][delay:]
            self.assertLess(np.max(np.abs(y_own[k][delay:] - clean[k][delay:] * np.exp(1j * want))), 1e-5 * rms, k)
        # Element 0 is the same chain either way (to rounding: VOLK's kernels take other paths on
        # buffers of other alignment).
        np.testing.assert_allclose(y_own[0], y_shared[0], rtol=0, atol=1e-6)
        # Own oscillators are independent: their increments over 20 samples are uncorrelated.
        inc = [np.diff(p[::delay]) for p in phases[1:3]]
        self.assertLess(abs(np.corrcoef(inc[0], inc[1])[0, 1]), 0.1)
        self.assertGreater(np.std(inc[0]), 0.5 * math.sqrt(delay * d_phi / FS))
        # A stream count other than the array's is refused naming both; "own" needs phase noise.
        with self.assertRaises(ValueError) as e:
            front_end(scene=scene, n_receive=2)
        self.assertIn("4", str(e.exception))
        self.assertIn("2", str(e.exception))
        with self.assertRaises(ValueError) as e:
            front_end(scene=scene, n_receive=n_rx, element_oscillators="own")
        self.assertIn("element_oscillators", str(e.exception))
        with self.assertRaises(ValueError) as e:
            front_end(scene=scene, n_receive=n_rx, phase_noise_dbc_hz=dbc, element_oscillators="each")
        self.assertIn("element_oscillators", str(e.exception))

    def test_iq_image_rejection(self):
        """A tone's image: |mu|^2 / |nu|^2 = (1 + g^2 + 2 g cos p) / (1 + g^2 - 2 g cos p), within 0.1 dB."""
        m, frames = 5, 4
        n = np.arange(frames * N * S)
        x = np.exp(2j * np.pi * m * n / M).astype(np.complex64)  # a subcarrier: CP-OFDM already
        for gain_db, phase_deg in ((0.5, 3.0), (-1.0, 0.0), (0.0, -5.0)):
            y, _ = run(front_end(scene=still_target(0.0), iq_gain_db=gain_db, iq_phase_deg=phase_deg), x)
            spec = np.abs(np.fft.fft(y[:len(y) // M * M])) ** 2
            k = len(spec) * m // M
            measured = 10 * math.log10(spec[k] / spec[-k])
            g, p = 10 ** (gain_db / 20), math.radians(phase_deg)
            closed = 10 * math.log10((1 + g * g + 2 * g * math.cos(p)) / (1 + g * g - 2 * g * math.cos(p)))
            s = sems.radio_settings(iq_gain_db=gain_db, iq_phase_deg=phase_deg)
            self.assertAlmostEqual(closed, 10 * math.log10(abs(s.iq_mu()) ** 2 / abs(s.iq_nu()) ** 2), delta=1e-9)
            self.assertAlmostEqual(measured, closed, delta=0.1, msg=f"{gain_db} dB, {phase_deg} deg")

    def test_converter_sqnr(self):
        """Complex Gaussian in: SQNR within 1 dB of the closed form (granular + clipping) in three regimes."""
        x = gaussian(820 * N * S)  # whole symbols: the channel works in symbols
        # Clipping-dominated (12 bits at 3.5x: 4.6e-4 of the rail samples clip), granular-dominated,
        # heavy clipping. (At 4x the clipped samples are so rare that 2e6 samples vary by +-0.7 dB.)
        # And 20 bits, past the 16-bit integers a converter model might round through.
        for enob, k in ((12, 3.5), (8, 8.0), (10, 2.0), (20, 8.0)):
            fe = front_end(scene=still_target(0.0), adc_enob=enob, adc_full_scale_rms=k)
            self.assertAlmostEqual(fe.full_scale(), k / math.sqrt(2), delta=1e-12)
            y, _ = run(fe, x)
            measured = 10 * math.log10(np.mean(np.abs(x) ** 2) / np.mean(np.abs(y - x) ** 2))
            closed = sqnr_closed_form_db(enob, k)
            self.assertAlmostEqual(measured, closed, delta=1.0, msg=f"ENOB {enob}, full scale {k}x rms")
            rails = np.concatenate([y.real, y.imag]) / fe.full_scale()
            self.assertLessEqual(np.max(np.abs(rails)), 1.0 + 1e-6)  # clipped at full scale

    def test_leakage_power_and_alignment(self):
        """The leakage is FIR(h) of the transmitted samples, sample-aligned, at 40 dB over the echo."""
        frames, seed = 20, 4
        x = ofdm(frames)
        scene = still_target(50.0)
        echo, _ = run(channel(scene=scene, seed=seed, snr_db=20.0), x)
        fe = front_end(scene=scene, seed=seed, snr_db=20.0, leakage_db=40.0)
        y, _ = run(fe, x)
        leak = y - echo
        h = np.array(fe.settings.leakage_response())
        want = np.convolve(x, h)[:len(x)]
        self.assertLess(np.max(np.abs(leak - want)), 1e-3 * np.max(np.abs(want)))
        # The echo's mean power is the transmitted power times the channel's unit power gain.
        ratio_db = 10 * math.log10(np.mean(np.abs(leak) ** 2) / np.mean(np.abs(x) ** 2))
        self.assertAlmostEqual(ratio_db, 40.0, delta=0.2)

    def test_ideal_radio_is_the_channel_alone(self):
        frames = 6
        x = ofdm(frames)
        kw = dict(scene="", classes=["car", "drone"], snr_db=10.0, seed=9)
        want, want_tags = run(channel(**kw), x, frame_tags(frames))
        for radio in ("", os.path.join(RADIOS, "ideal.json")):
            got, got_tags = run(front_end(radio, **kw), x, frame_tags(frames))
            np.testing.assert_array_equal(got, want)
            self.assertEqual([(t.offset, pmt.symbol_to_string(t.key)) for t in got_tags],
                             [(t.offset, pmt.symbol_to_string(t.key)) for t in want_tags])

    def test_impaired_radios_keep_tags_and_length(self):
        """Every stage lets each tag through once (iqbal_gen and the converter's rails would copy them)."""
        frames = 4
        x = ofdm(frames)
        for radio in ("sdr_monostatic.json", "sdr_bistatic.json"):
            y, tags = run(front_end(os.path.join(RADIOS, radio), snr_db=20.0), x, frame_tags(frames))
            keys = [pmt.symbol_to_string(t.key) for t in tags]
            self.assertEqual(keys.count(sems.keys.frame_tag), frames, radio)
            self.assertEqual(keys.count(sems.keys.truth_tag), frames, radio)
            if radio == "sdr_monostatic.json":
                self.assertEqual(len(y), len(x))
                self.assertEqual([t.offset for t in tags if pmt.symbol_to_string(t.key) == sems.keys.frame_tag],
                                 [f * N * S for f in range(frames)])

    def test_cfo_rotates(self):
        x = ofdm(2)
        scene = still_target(0.0)
        clean, _ = run(channel(scene=scene), x)
        y, _ = run(front_end(scene=scene, oscillator="separate", cfo_hz=12345.0), x)
        n = np.arange(len(x))
        np.testing.assert_allclose(y, clean * np.exp(2j * np.pi * 12345.0 * n / FS), atol=1e-4)

    def test_sfo_resamples_without_shift(self):
        """Output k is the input at k / (1 + sfo): no delay from the interpolator (a tone well inside the band)."""
        ppm = 200.0
        n = np.arange(4 * N * S)
        x = np.exp(2j * np.pi * n / M).astype(np.complex64)
        y, _ = run(front_end(scene=still_target(0.0), oscillator="separate", sfo_ppm=ppm), x)
        k = np.arange(8, len(y))
        want = np.exp(2j * np.pi * (k / (1 + 1e-6 * ppm)) / M)
        self.assertLess(np.max(np.abs(y[8:] - want)), 1e-3)

    def test_converter_full_scale_without_a_flowgraph(self):
        """sems.converter_full_scale equals the block's full_scale() for the shipped radios, keyword
        overrides, SNRs and transmitted powers; it follows the closed form k * rms / sqrt(2); an
        ideal converter has none (0.0, the leakage canceller's "nothing clips")."""
        mono, bi = os.path.join(RADIOS, "sdr_monostatic.json"), os.path.join(RADIOS, "sdr_bistatic.json")
        with open(mono) as f:
            mono_text = f.read()
        cases = [(mono, 20.0, 1.0, {}), (mono, 10.0, 1.0, {"adc_full_scale_rms": 8.0}),
                 (mono, 20.0, 52 / 64, {"leakage_db": 30.0}), (bi, 20.0, 1.0, {}),
                 ("", 5.0, 1.0, {"adc_enob": 10.0, "adc_full_scale_rms": 3.0}),
                 (mono_text, float("inf"), 1.0, {})]
        for radio, snr_db, tx_power, kw in cases:
            fe = front_end(radio, snr_db=snr_db, tx_power=tx_power, **kw)
            got = sems.converter_full_scale(radio, snr_db, tx_power, **kw)
            self.assertGreater(got, 0.0)
            self.assertEqual(got, fe.full_scale(), f"{radio[:40]} {snr_db} dB {kw}")
            self.assertEqual(got, sems.converter_full_scale(fe.settings, snr_db, tx_power))
        # The closed form: leakage L dB over the echo, noise 10^(-SNR/10), no IQ imbalance or DC.
        want = 4.0 * math.sqrt(1.0 + 1e4 + 0.01) / math.sqrt(2.0)
        self.assertAlmostEqual(sems.converter_full_scale(leakage_db=40.0, adc_enob=12.0, snr_db=20.0), want,
                               delta=1e-12 * want)
        # A changed SNR moves the block's full scale with it, as the function says.
        fe = front_end(mono, snr_db=20.0)
        fe.set_snr_db(0.0)
        self.assertEqual(fe.full_scale(), sems.converter_full_scale(mono, 0.0))
        # An ideal converter: nothing clips, no full scale, whatever the rest of the radio.
        for radio, kw in (("", {}), (os.path.join(RADIOS, "ideal.json"), {}), (mono, {"adc_enob": None}),
                          ("", {"leakage_db": 40.0, "adc_full_scale_rms": 2.0})):
            self.assertEqual(sems.converter_full_scale(radio, 20.0, **kw), 0.0)
            self.assertEqual(front_end(radio, snr_db=20.0, **kw).full_scale(), 0.0)
        # Bad input named, as the block names it.
        with self.assertRaises(ValueError) as e:
            sems.converter_full_scale(mono, 20.0, 0.0)
        self.assertIn("tx_power", str(e.exception))
        with self.assertRaises(ValueError) as e:
            sems.converter_full_scale(mono, float("nan"))
        self.assertIn("snr_db", str(e.exception))
        with self.assertRaises(ValueError) as e:
            sems.converter_full_scale(adc_full_scale_rms=-1.0, adc_enob=12.0)
        self.assertIn("adc_full_scale_rms", str(e.exception))
        with self.assertRaises(TypeError):
            sems.converter_full_scale(mono, adc_bits=12)

    def test_recording_says_the_full_scale(self):
        """write_recording_info writes the converter's full scale next to a recording and
        recorded_full_scale reads it back; a recording without it gives 0.0 with a note; a
        broken record is refused naming the file and the key."""
        import contextlib
        import io
        import tempfile
        mono = os.path.join(RADIOS, "sdr_monostatic.json")
        with tempfile.TemporaryDirectory() as d:
            rec = os.path.join(d, "rec.c64")
            fe = front_end(mono, snr_db=20.0, adc_full_scale_rms=8.0)
            written = sems.write_recording_info(rec, fe.settings, fe.snr_db(), fe.tx_power)
            self.assertEqual(written, fe.full_scale())
            self.assertEqual(sems.recorded_full_scale(rec), fe.full_scale())
            with open(rec + ".json") as f:
                info = json.load(f)
            self.assertEqual(sems.front_end_settings.parse(json.dumps(info["radio"])), fe.settings)
            self.assertEqual(info["snr_db"], 20.0)
            # An ideal converter records 0.0; infinite SNR is recorded as null.
            self.assertEqual(sems.write_recording_info(rec, "", float("inf")), 0.0)
            self.assertEqual(sems.recorded_full_scale(rec), 0.0)
            with open(rec + ".json") as f:
                self.assertIsNone(json.load(f)["snr_db"])
            # A recording made without the record: clip level 0 and a note naming the file.
            old = os.path.join(d, "old.c64")
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                self.assertEqual(sems.recorded_full_scale(old), 0.0)
            self.assertIn(old + ".json", err.getvalue())
            self.assertIn("clip_level 0", err.getvalue())
            for text, key in (("{", "not JSON"), ('{"format": "sems.radio", "version": 1}', "format"),
                              ('{"format": "sems.radio_recording", "version": 2, "converter_full_scale": 1}', "version"),
                              ('{"format": "sems.radio_recording", "version": 1}', "converter_full_scale"),
                              ('{"format": "sems.radio_recording", "version": 1, "converter_full_scale": -1}',
                               "converter_full_scale")):
                with open(rec + ".json", "w") as f:
                    f.write(text)
                with self.assertRaises(ValueError) as e:
                    sems.recorded_full_scale(rec)
                self.assertIn(rec + ".json", str(e.exception))
                self.assertIn(key, str(e.exception))

    def test_bad_settings_are_named(self):
        cases = [(dict(adc_enob=-1.0), "adc_enob"), (dict(phase_noise_dbc_hz=3.0), "phase_noise_dbc_hz"),
                 (dict(phase_noise_dbc_hz=-90.0, phase_noise_offset_hz=-1.0), "phase_noise_offset_hz"),
                 (dict(adc_full_scale_rms=0.0), "adc_full_scale_rms"), (dict(leakage_db=float("nan")), "leakage_db"),
                 (dict(cfo_hz=10.0), "cfo_hz"), (dict(iq_phase_deg=95.0), "iq_phase_deg")]
        for kw, name in cases:
            with self.assertRaises(ValueError) as e:
                front_end(**kw)
            self.assertIn(name, str(e.exception))
        with self.assertRaises(TypeError):
            front_end(adc_bits=12)
        with self.assertRaises(ValueError) as e:
            front_end(tx_power=0.0)
        self.assertIn("tx_power", str(e.exception))
        with self.assertRaises(ValueError) as e:
            front_end('{"format": "sems.radio", "version": 1, "leakag": {}}')
        self.assertIn("leakag", str(e.exception))
        with self.assertRaises(ValueError) as e:
            sems.phase_noise_source(30e6, 1.0, 100e3, 0)
        self.assertIn("phase_noise_dbc_hz", str(e.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_radio_front_end)
