#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: cfo_corrector, the block: a CP-OFDM stream from ofdm_tx with a carrier frequency
offset, started at a random sample, in noise: the offset is estimated within the closed
form's spread (core cp_sync.h) and removed, the output the transmitted stream up to a
constant phase; on an echo-only link through target_channel_td, a still echo gives 0 and a
pure offset on it is recovered, and a moving echo reads its Doppler (and nothing more: the
echo of one symbol keeps one slow time, core td_channel.h); bad parameters are refused by
name."""
import json
import math

import numpy as np
from gnuradio import analog, blocks, digital, gr, gr_unittest, sems

QPSK = [(1 + 1j) / 2 ** 0.5, (-1 + 1j) / 2 ** 0.5, (-1 - 1j) / 2 ** 0.5, (1 - 1j) / 2 ** 0.5]


def ofdm_stream(symbols, m, cp, seed):
    src = digital.chunks_to_symbols_bc(QPSK, 1)
    tb = gr.top_block()
    sink = blocks.vector_sink_c()
    tb.connect(analog.random_uniform_source_b(0, 4, seed), src, blocks.stream_to_vector(gr.sizeof_gr_complex, m),
               blocks.head(gr.sizeof_gr_complex * m, symbols), sems.ofdm_tx(m, cp), sink)
    tb.run()
    return np.array(sink.data(), dtype=np.complex64)


class qa_cfo_corrector(gr_unittest.TestCase):

    def test_001_offset_estimated_and_removed(self):
        m, cp, symbols, windows = 64, 16, 32, 10
        rng = np.random.default_rng(1)
        for cfo in (-0.31, 0.17):
            with self.subTest(cfo=cfo):
                start = int(rng.integers(1, m + cp))
                tx = ofdm_stream(symbols * windows + 2, m, cp, seed=3)[start:start + symbols * windows * (m + cp)]
                k = np.arange(tx.size)
                snr = 100.0  # 20 dB
                noise = (rng.standard_normal(tx.size) + 1j * rng.standard_normal(tx.size)) * math.sqrt(0.5 / snr)
                rx = (tx * np.exp(2j * np.pi * cfo * k / m) + noise).astype(np.complex64)
                cc = sems.cfo_corrector(m, cp, symbols, 0.5, 20.0)
                sink = blocks.vector_sink_c()
                tb = gr.top_block()
                tb.connect(blocks.vector_source_c(rx.tolist()), cc, sink)
                tb.run()
                y = np.array(sink.data(), dtype=np.complex64)
                self.assertEqual(y.size, rx.size)
                self.assertEqual(cc.windows(), windows)
                self.assertEqual(cc.timing(), (m + cp - start) % (m + cp))
                # one window's spread (cp_sync.h), averaging only narrows it
                sd = math.sqrt((1 / snr + 1 / (2 * snr ** 2)) / (4 * math.pi ** 2 * (symbols - 1) * cp))
                self.assertLess(abs(cc.cfo() - cfo), 5 * sd)
                # after the first windows: the transmitted stream up to one constant phase
                w = symbols * (m + cp)
                a, b = y[3 * w:], tx[3 * w:]
                coherence = abs(np.vdot(b, a)) / math.sqrt(np.vdot(a, a).real * np.vdot(b, b).real)
                self.assertGreater(coherence, 0.98)
                uncorrected = abs(np.vdot(b, rx[3 * w:])) / math.sqrt(
                    np.vdot(rx[3 * w:], rx[3 * w:]).real * np.vdot(b, b).real)
                self.assertLess(uncorrected, 0.1)

    def echo_cfo(self, delay, speed, cfo=0.0, snr_db=20.0):
        """cfo_corrector's estimate (subcarrier spacings) on one point echo of the paper's frame
        (3 GHz, 30 MHz, M 64, CP 16, T 1 ms) `delay` samples late, through target_channel_td,
        with a frequency offset `cfo` (spacings) added after the channel; and ν/Δf."""
        m, cp, symbols, frames = 64, 16, 32, 4
        b, fc = 30e6, 3e9
        scene = json.dumps({"format": "sems.scene", "version": 1, "classes": "paper", "fading": "none",
                            "targets": [{"class": "car", "range_m": delay * 3e8 / (2 * b), "speed_mps": speed,
                                         "heading_rad": 0}]})
        tx = ofdm_stream(symbols * frames, m, cp, seed=5)
        tb = gr.top_block()
        ch = sems.target_channel_td(scene, snr_db=snr_db, seed=2, n_symbols=symbols, n_subcarriers=m,
                                    bandwidth_hz=b, carrier_hz=fc, symbol_interval_s=1e-3, cp_len=cp)
        rot = blocks.rotator_cc(2 * math.pi * cfo / m)
        cc = sems.cfo_corrector(m, cp, symbols, 0.5, snr_db if math.isfinite(snr_db) else 60.0)
        tb.connect(blocks.vector_source_c(tx.tolist()), ch, rot, cc, blocks.null_sink(gr.sizeof_gr_complex))
        tb.run()
        self.assertEqual(cc.windows(), frames)
        return cc.cfo(), 2 * speed * fc / 3e8 / (b / m)

    def test_003_echo_only_link(self):
        m, cp, symbols = 64, 16, 32
        snr = 100.0  # 20 dB
        sd = math.sqrt((1 / snr + 1 / (2 * snr ** 2)) / (4 * math.pi ** 2 * (symbols - 1) * cp))
        for delay in (5, 23):  # inside and past the prefix
            with self.subTest(delay=delay):
                # a still echo: no offset
                est, _ = self.echo_cfo(delay, 0.0)
                self.assertLess(abs(est), 5 * sd)
                # a pure offset on the still echo: recovered
                est, _ = self.echo_cfo(delay, 0.0, cfo=0.13)
                self.assertLess(abs(est - 0.13), 5 * sd)
                # a moving echo, noiseless: exactly its Doppler in spacings (20 m/s at 3 GHz:
                # 400 Hz, 8.5e-4 spacings), not ν·T (0.4: the bias when the tail of each
                # symbol's echo took the next symbol's slow time)
                est, nu = self.echo_cfo(delay, 20.0, snr_db=float("inf"))
                self.assertAlmostEqual(est, nu, delta=1e-5)

    def test_002_bad_parameters_refused_by_name(self):
        for kw, name in (({"n_subcarriers": 0}, "n_subcarriers"), ({"cp_len": 0}, "cp_len"),
                         ({"cp_len": 65}, "cp_len"), ({"symbols": 1}, "symbols"),
                         ({"forgetting": 1.0}, "forgetting"), ({"snr_db": float("inf")}, "snr_db")):
            with self.subTest(**kw):
                with self.assertRaisesRegex(ValueError, name):
                    sems.cfo_corrector(**kw)


if __name__ == "__main__":
    gr_unittest.run(qa_cfo_corrector)
