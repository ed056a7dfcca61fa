#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: ofdm_tx -> ofdm_rx is the identity (inverse FFT + cyclic prefix, and back)."""
import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems


def symbols(rows, m, seed=1):
    rng = np.random.default_rng(seed)
    return (rng.standard_normal((rows, m)) + 1j * rng.standard_normal((rows, m))).astype(np.complex64)


class qa_ofdm_tx_rx(gr_unittest.TestCase):

    def loop(self, x, m, cp, tags=()):
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=m, tags=list(tags))
        tx = sems.ofdm_tx(m, cp)
        rx = sems.ofdm_rx(m, cp)
        time_sink = blocks.vector_sink_c()
        sink = blocks.vector_sink_c(m)
        tb = gr.top_block()
        tb.connect(src, tx, rx, sink)
        tb.connect(tx, time_sink)
        tb.run()
        return np.array(sink.data()).reshape(-1, m), np.array(time_sink.data()), sink.tags()

    def test_001_identity(self):
        for m, cp in ((64, 16), (8, 0), (16, 16)):
            with self.subTest(m=m, cp=cp):
                x = symbols(20, m)
                y, t, _ = self.loop(x, m, cp)
                np.testing.assert_allclose(y, x, rtol=1e-5, atol=1e-5)
                # M + cp samples per symbol; the prefix is the symbol's tail; power kept (unitary)
                t = t.reshape(-1, m + cp)
                self.assertEqual(t.shape[0], 20)
                np.testing.assert_allclose(t[:, :cp], t[:, m:], rtol=1e-6)
                np.testing.assert_allclose(t[:, cp:], np.fft.ifft(x, axis=1) * np.sqrt(m), rtol=1e-4, atol=1e-5)
                self.assertAlmostEqual(np.mean(np.abs(t[:, cp:]) ** 2) / np.mean(np.abs(x) ** 2), 1.0, places=5)

    def test_002_frame_tags_survive(self):
        m, cp, n = 64, 16, 4
        x = symbols(3 * n, m)
        key = pmt.intern(sems.keys.frame_tag)
        tags = [gr.tag_utils.python_to_tag((f * n, key, pmt.from_uint64(f))) for f in range(3)]
        _, _, out_tags = self.loop(x, m, cp, tags)
        got = [(t.offset, pmt.to_uint64(t.value)) for t in out_tags if pmt.eqv(t.key, key)]
        self.assertEqual(got, [(f * n, f) for f in range(3)])

    def test_003_sensing_chain_through_time_domain(self):
        # mapper -> ofdm_tx -> ofdm_rx -> channel -> extractor: the same pilots, tags
        # and frame indices as without the time-domain step (float tolerance).
        n, m, cp, frames = 4, 16, 4, 3
        pos = [1, 18, 40, 63]
        b = m * 468.75e3

        def run(time_domain):
            mapper = sems.pilot_mapper(pilot_positions=pos, n_symbols=n, n_subcarriers=m, pilot_power=2.0)
            src = blocks.vector_source_c(symbols(frames * (n * m - len(pos)), 1).ravel().tolist())
            chain = [src, mapper]
            if time_domain:
                chain += [sems.ofdm_tx(m, cp), sems.ofdm_rx(m, cp)]
            chain += [sems.target_channel(seed=3, n_symbols=n, n_subcarriers=m, bandwidth_hz=b),
                      sems.pilot_extractor(pilot_positions=pos, n_symbols=n, n_subcarriers=m)]
            sink = blocks.vector_sink_c(len(pos))
            tb = gr.top_block()
            tb.connect(*chain, sink)
            tb.run()
            tags = [(t.offset, pmt.symbol_to_string(t.key)) for t in sink.tags()]
            return np.array(sink.data()).reshape(-1, len(pos)), sorted(tags)

        direct, direct_tags = run(False)
        looped, looped_tags = run(True)
        self.assertEqual(direct.shape, (frames, len(pos)))
        np.testing.assert_allclose(looped, direct, rtol=1e-5, atol=1e-5)
        self.assertEqual(looped_tags, direct_tags)

    def test_004_bad_parameters(self):
        with self.assertRaises(ValueError):
            sems.ofdm_tx(64, -1)
        with self.assertRaises(ValueError):
            sems.ofdm_rx(0, 16)


if __name__ == "__main__":
    gr_unittest.run(qa_ofdm_tx_rx)
