#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: cfo_corrector, the block: a CP-OFDM stream from ofdm_tx with a carrier frequency
offset, started at a random sample, in noise: the offset is estimated within the closed
form's spread (core cp_sync.h) and removed, the output the transmitted stream up to a
constant phase; bad parameters are refused by name."""
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

    def test_002_bad_parameters_refused_by_name(self):
        for kw, name in (({"n_subcarriers": 0}, "n_subcarriers"), ({"cp_len": 0}, "cp_len"),
                         ({"cp_len": 65}, "cp_len"), ({"symbols": 1}, "symbols"),
                         ({"forgetting": 1.0}, "forgetting"), ({"snr_db": float("inf")}, "snr_db")):
            with self.subTest(**kw):
                with self.assertRaisesRegex(ValueError, name):
                    sems.cfo_corrector(**kw)


if __name__ == "__main__":
    gr_unittest.run(qa_cfo_corrector)
