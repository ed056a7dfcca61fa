#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: leakage_canceller, the block: a static leakage of L taps with its IQ image and
DC is cancelled by >= 60 dB, an echo delayed past the taps passes within 0.1 dB, rx's tags
stay on their samples, bad parameters are refused by name; and in the receiver chain
(mapper -> ofdm_tx -> target_channel_td at 20 dB, the transmitted samples leaking in 40 dB
over the echo with their IQ image and DC -> leakage_canceller -> ofdm_rx) the echo's
per-resource-element channel comes out as without leakage. With frame_sync in one flowgraph
(ofdm_tx -> radio_front_end -> unknown latency -> frame_sync -> canceller, ofdm_tx -> the
canceller's tx; and the other order) the flowgraph ends within a timeout, every frame comes out
with its frame and truth tags on its first sample and the leakage is cancelled; a received
stream that never starts stops the block with an error once the held samples pass the limit."""
import json
import os
import threading

import numpy as np
import pmt
from gnuradio import analog, blocks, digital, gr, gr_unittest, sems

W = 2560  # the default window: one frame N(M + CP)
QPSK = [(1 + 1j) / 2 ** 0.5, (-1 + 1j) / 2 ** 0.5, (-1 - 1j) / 2 ** 0.5, (1 - 1j) / 2 ** 0.5]


def cn(rng, n, var=1.0):
    return ((rng.standard_normal(n) + 1j * rng.standard_normal(n)) * np.sqrt(var / 2)).astype(np.complex64)


def leak(tx, h, g, c):
    """sum_d h_d tx[n-d] + g_d conj(tx[n-d]) + c: the leakage, its IQ image, DC"""
    return (np.convolve(tx, h)[:tx.size] + np.convolve(np.conj(tx), g)[:tx.size] + c).astype(np.complex64)


def cancel(rx, tx, tags=(), **kw):
    lc = sems.leakage_canceller(**kw)
    src_rx = blocks.vector_source_c(rx.tolist(), tags=list(tags))
    src_tx = blocks.vector_source_c(tx.tolist())
    sink = blocks.vector_sink_c()
    tb = gr.top_block()
    tb.connect(src_rx, (lc, 0))
    tb.connect(src_tx, (lc, 1))
    tb.connect(lc, sink)
    tb.run()
    return lc, np.array(sink.data(), dtype=np.complex64), sink.tags()


class qa_leakage_canceller(gr_unittest.TestCase):

    def test_001_static_leakage_image_dc_cancelled_60_db(self):
        rng = np.random.default_rng(1)
        h = cn(rng, 4, 1e4)  # 40 dB
        g = h * (0.02 + 0.03j)
        tx = cn(rng, 8 * W)
        rx = leak(tx, h, g, 2 - 1j)
        lc, y, _ = cancel(rx, tx)
        self.assertEqual(y.size, rx.size)
        self.assertEqual(lc.windows(), 8)
        db = 10 * np.log10(np.mean(np.abs(y) ** 2) / np.mean(np.abs(rx) ** 2))
        self.assertLess(db, -60.0)
        np.testing.assert_allclose(lc.taps(), h, rtol=0, atol=1e-3 * np.abs(h).max())
        np.testing.assert_allclose(lc.image_taps(), g, rtol=0, atol=1e-3 * np.abs(h).max())
        self.assertAlmostEqual(lc.dc(), 2 - 1j, delta=1e-3)

    def test_002_echo_past_the_taps_passes_tags_kept(self):
        rng = np.random.default_rng(2)
        h = cn(rng, 4, 1e4)
        tx = cn(rng, 12 * W)
        echo = np.zeros_like(tx)
        echo[30:] = (0.6 - 0.8j) * tx[:-30]
        rx = leak(tx, h, h * 0.03j, 0.5) + echo
        key = pmt.intern("mark")
        tags = [gr.tag_utils.python_to_tag((k * 1000 + 7, key, pmt.from_long(k))) for k in range(20)]
        _, y, out_tags = cancel(rx, tx, tags)
        db = 10 * np.log10(np.mean(np.abs(y[W:]) ** 2) / np.mean(np.abs(echo[W:]) ** 2))
        self.assertLess(abs(db), 0.1)
        # sample by sample, once the forgetting has averaged a few windows: the echo, the
        # leakage 30 dB under it
        self.assertLess(np.mean(np.abs(y[4 * W:] - echo[4 * W:]) ** 2), 1e-3 * np.mean(np.abs(echo[4 * W:]) ** 2))
        # rx's tags on their samples, once each (tx carries none here; it would be dropped)
        got = sorted((t.offset, pmt.to_long(t.value)) for t in out_tags if pmt.eqv(t.key, key))
        self.assertEqual(got, [(k * 1000 + 7, k) for k in range(20)])

    def test_003_bad_parameters_refused_by_name(self):
        for kw, name in (({"taps": 0}, "taps"), ({"taps": 65}, "taps"), ({"window": 8}, "window"),
                         ({"forgetting": 1.0}, "forgetting"), ({"forgetting": -0.5}, "forgetting"),
                         ({"clip_level": -1.0}, "clip_level"), ({"clip_level": float("inf")}, "clip_level")):
            with self.subTest(**kw):
                with self.assertRaisesRegex(ValueError, name):
                    sems.leakage_canceller(**kw)

    def test_003b_clipped_leakage_with_the_full_scale_given(self):
        # The leakage 40 dB over an echo 30 samples behind, each rail clipped at 3x its rms
        # (about 0.3 % of the rails): the clipped overshoot lands on the output unless the
        # block is told the converter's full scale; then what is left is at most the echo's own
        # value on the clipped rails, >= 20 dB under the echo.
        rng = np.random.default_rng(5)
        h = cn(rng, 4, 1e4 / 4)
        tx = cn(rng, 12 * W)
        echo = np.zeros_like(tx)
        echo[30:] = (0.6 - 0.8j) * tx[:-30]
        clean = leak(tx, h, 0 * h, 0) + echo
        fs = np.float32(3.0 * np.sqrt(np.mean(np.abs(clean) ** 2) / 2))
        rx = (np.clip(clean.real, -fs, fs) + 1j * np.clip(clean.imag, -fs, fs)).astype(np.complex64)
        self.assertGreater(np.mean(np.abs(rx.real) >= fs), 0.001)
        errors = {}
        for level in (0.0, float(fs)):
            _, y, _ = cancel(rx, tx, clip_level=level)
            errors[level] = 10 * np.log10(np.mean(np.abs(y[W:] - echo[W:]) ** 2) / np.mean(np.abs(echo[W:]) ** 2))
        self.assertGreater(errors[0.0], 0.0)
        self.assertLess(errors[float(fs)], -20.0)

    def test_004_echo_channel_through_the_receiver_chain(self):
        # 24 frames of the delay mask through ofdm_tx and target_channel_td (a car at 60 m,
        # 12 samples, moving at 10 m/s, 20 dB SNR); the transmitted samples leak in at 40 dB
        # over the echo with 3 taps, their IQ image 25 dB under the leakage and a DC.
        n, m, cp, frames = 32, 64, 16, 24
        mask = os.path.join(os.environ.get("SEMS_SOURCE_DIR", "."), "models", "delay_single", "mask.json")
        scene = json.dumps({"format": "sems.scene", "version": 1, "fading": "none", "targets": [
            {"class": "car", "range_m": 60.0, "velocity_mps": 10.0, "power": 1,
             "paths": [{"excess_range_m": 0.0, "power": 1}]}]})
        bits = analog.random_uniform_source_b(0, 4, 5)
        mapper = sems.pilot_mapper(mask_file=mask)
        head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
        ofdm = sems.ofdm_tx(m, cp)
        ch = sems.target_channel_td(scene=scene, snr_db=20.0, seed=3, cp_len=cp)
        x_sink, tx_sink, echo_sink = blocks.vector_sink_c(m), blocks.vector_sink_c(), blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(bits, digital.chunks_to_symbols_bc(QPSK, 1), mapper, head, ofdm, ch, echo_sink)
        tb.connect(head, x_sink)
        tb.connect(ofdm, tx_sink)
        tb.run()
        x = np.array(x_sink.data(), dtype=np.complex64).reshape(-1, m)
        tx = np.array(tx_sink.data(), dtype=np.complex64)
        echo = np.array(echo_sink.data(), dtype=np.complex64)
        rng = np.random.default_rng(6)
        h = cn(rng, 3, 1e4) / np.sqrt(3)
        rx = leak(tx, h, h * 10 ** (-25 / 20) * np.exp(0.7j), 1.5 + 0.5j) + echo
        self.assertGreater(10 * np.log10(np.mean(np.abs(rx - echo) ** 2) / np.mean(np.abs(tx) ** 2)), 39.0)

        def receive(samples, with_canceller):
            src = blocks.vector_source_c(samples.tolist())
            sink = blocks.vector_sink_c(m)
            tb = gr.top_block()
            if with_canceller:
                lc = sems.leakage_canceller(taps=4, window=n * (m + cp))
                tb.connect(src, (lc, 0))
                tb.connect(blocks.vector_source_c(tx.tolist()), (lc, 1))
                tb.connect(lc, sems.ofdm_rx(m, cp), sink)
            else:
                tb.connect(src, sems.ofdm_rx(m, cp), sink)
            tb.run()
            return np.array(sink.data(), dtype=np.complex64).reshape(-1, m)

        h_free = receive(echo, False) / x  # the echo's per-RE channel without leakage
        h_canc = receive(rx, True) / x
        h_leak = receive(rx, False) / x
        skip = 4 * n  # the fit's first frames (forgetting 0.9 still filling)
        ref = np.mean(np.abs(h_free[skip:]) ** 2)
        err = np.mean(np.abs(h_canc[skip:] - h_free[skip:]) ** 2) / ref
        before = np.mean(np.abs(h_leak[skip:] - h_free[skip:]) ** 2) / ref
        self.assertGreater(10 * np.log10(before), 39.0)
        # below the channel's own noise (20 dB under the echo) by 10 dB
        self.assertLess(10 * np.log10(err), -30.0, f"error {10 * np.log10(err):.1f} dB")

    def _monostatic_chain(self, order, latency, frames=12):
        """mapper -> ofdm_tx -> radio_front_end (examples/radios/sdr_monostatic.json, 20 dB) ->
        the radio's latency -> frame_sync and leakage_canceller in `order`, the canceller fed
        with the transmitted samples -> vector sink. Runs it with a timeout; returns the parts."""
        n, m, cp = 32, 64, 16
        src = os.environ.get("SEMS_SOURCE_DIR", ".")
        mask = os.path.join(src, "models", "delay_single", "mask.json")
        radio = os.path.join(src, "examples", "radios", "sdr_monostatic.json")
        scene = json.dumps({"format": "sems.scene", "version": 1, "fading": "none", "targets": [
            {"class": "car", "range_m": 60.0, "velocity_mps": 10.0, "power": 1,
             "paths": [{"excess_range_m": 0.0, "power": 1}]}]})
        L = n * (m + cp)
        head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
        ofdm = sems.ofdm_tx(m, cp)
        fe = sems.radio_front_end(radio, scene=scene, snr_db=20.0, seed=4, cp_len=cp)
        late = blocks.delay(gr.sizeof_gr_complex, latency)  # the radio's TX-to-RX latency, unknown
        if order == "sync first":  # on the leakage, which is the same in every frame
            fsync = sems.frame_sync(mask_file=mask, n_symbols=n, n_subcarriers=m, cp_len=cp)
        else:
            # After the canceller little of the leakage is left, so frame_sync times the frames
            # on the moving echo, whose phase turns from frame to frame: non-coherent search, at
            # the threshold of 1e-6 false locks per search (frame_search::threshold_for(1e-6, 4,
            # 2560, true), frame_search.h)
            fsync = sems.frame_sync(mask_file=mask, n_symbols=n, n_subcarriers=m, cp_len=cp, noncoherent=True,
                                    threshold=30.2)
        lc = sems.leakage_canceller(taps=4, window=L)
        rx_sink, out_sink = blocks.vector_sink_c(), blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(analog.random_uniform_source_b(0, 4, 5), digital.chunks_to_symbols_bc(QPSK, 1),
                   sems.pilot_mapper(mask_file=mask), head, ofdm, fe, late)
        if order == "sync first":
            tb.connect(late, fsync, (lc, 0))
            tb.connect(ofdm, (lc, 1))
            tb.connect(fsync, rx_sink)
            tb.connect(lc, out_sink)
        else:  # the transmitted samples delayed by the latency, cancelled before the search
            tb.connect(late, (lc, 0))
            tb.connect(ofdm, blocks.delay(gr.sizeof_gr_complex, latency), (lc, 1))
            tb.connect(lc, fsync, out_sink)
            tb.connect(late, rx_sink)
        tb.start()
        waiter = threading.Thread(target=tb.wait, daemon=True)
        waiter.start()
        waiter.join(timeout=120.0)
        if waiter.is_alive():
            tb.stop()
            self.fail(f"{order}: the flowgraph frame_sync + leakage_canceller did not finish within 120 s "
                      f"(frame_sync read {fsync.nitems_read(0)} samples, locked {fsync.locked()}, "
                      f"the canceller holds {lc.held()} transmitted samples)")
        return fsync, lc, rx_sink, out_sink, L

    def test_005_frame_sync_then_canceller_in_one_flowgraph(self):
        # frame_sync outputs nothing until it has searched (F + 1) frames past the latency; the
        # canceller holds the transmitted samples meanwhile, so the transmitter never waits.
        frames = 12
        key_frame, key_truth = pmt.intern(sems.keys.frame_tag), pmt.intern(sems.keys.truth_tag)
        for latency in (777, 5000):
            with self.subTest(latency=latency):
                fsync, lc, rx_sink, out_sink, L = self._monostatic_chain("sync first", latency, frames)
                self.assertEqual(lc.stream_error(), "")
                self.assertTrue(fsync.locked())
                self.assertEqual(fsync.offset(), latency)  # on the leakage, delay 0
                # every frame comes out (the latency's zeros come first, then the whole stream):
                # none held back, none lost
                whole = frames
                y = np.array(out_sink.data(), dtype=np.complex64)
                self.assertEqual(y.size, whole * L)
                self.assertEqual(lc.windows(), whole)
                # frame_sync's frame tags and the radio's truth tags on every frame's first
                # sample, frame k's truth on frame k: received frame k met transmitted frame k
                tags = out_sink.tags()
                got = sorted((t.offset, pmt.to_uint64(t.value)) for t in tags if pmt.eqv(t.key, key_frame))
                self.assertEqual(got, [(k * L, k) for k in range(whole)])
                truth = sorted((t.offset, pmt.to_uint64(pmt.dict_ref(t.value, pmt.intern(sems.keys.frame),
                                                                      pmt.PMT_NIL)))
                               for t in tags if pmt.eqv(t.key, key_truth))
                self.assertEqual(truth, [(k * L, k) for k in range(whole)])
                # the leakage (40 dB over the echo) is cancelled by more than 30 dB after 4
                # frames; what is left over the echo is mostly the converter's clipping of the
                # leakage (full scale 4x the rms), which no linear fit removes
                rx = np.array(rx_sink.data(), dtype=np.complex64)
                before = 10 * np.log10(np.mean(np.abs(rx[4 * L:]) ** 2))
                after = 10 * np.log10(np.mean(np.abs(y[4 * L:]) ** 2))
                self.assertGreater(before, 39.0)
                self.assertLess(after, before - 30.0)

    def test_006_canceller_then_frame_sync_in_one_flowgraph(self):
        # the other order: the transmitted samples delayed by the (here known) latency, the
        # canceller first; frame_sync then times the frames on what is left of the leakage
        # (delay 0) or, non-coherently, on the echo (the car at 60 m: 12 samples behind at 30 MHz)
        frames, latency = 12, 5000
        fsync, lc, _, out_sink, L = self._monostatic_chain("canceller first", latency, frames)
        self.assertEqual(lc.stream_error(), "")
        self.assertTrue(fsync.locked())
        self.assertIn(fsync.offset(), (latency, latency + 12))
        self.assertEqual(lc.windows(), (frames * L + latency) // L)  # the latency's zeros, then the stream
        got = sorted((t.offset, pmt.to_uint64(t.value)) for t in out_sink.tags()
                     if pmt.eqv(t.key, pmt.intern(sems.keys.frame_tag)))
        self.assertGreater(len(got), 0)
        self.assertEqual(got, [(k * L, k) for k in range(len(got))])

    def test_007_received_stream_never_starting_is_an_error(self):
        # frame_sync on noise finds no frame and outputs nothing; the transmitted
        # samples pile up to the block's limit, then it stops the stream naming both counts
        # (with a received stream that ends instead, the block ends with it)
        W = 2560
        limit = sems.leakage_canceller.max_lead(W)
        self.assertEqual(limit, max(64 * W, 1 << 20))
        mask = os.path.join(os.environ.get("SEMS_SOURCE_DIR", "."), "models", "delay_single", "mask.json")
        lc = sems.leakage_canceller(window=W)
        fsync = sems.frame_sync(mask_file=mask)
        tb = gr.top_block()
        # noise far longer than the transmission (a live radio that hears nothing it knows):
        # the transmitted samples have all arrived long before it ends
        tb.connect(analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 3), blocks.head(gr.sizeof_gr_complex, 8 * limit),
                   fsync, (lc, 0))
        tb.connect(blocks.null_source(gr.sizeof_gr_complex), blocks.head(gr.sizeof_gr_complex, limit + 4 * W),
                   (lc, 1))
        sink = blocks.vector_sink_c()
        tb.connect(lc, sink)
        tb.run()
        self.assertFalse(fsync.locked())
        self.assertEqual(len(sink.data()), 0)
        self.assertGreater(lc.held(), limit)
        self.assertRegex(lc.stream_error(), r"run \d+ samples ahead of the received ones \(input 0\), more than the "
                         + str(limit))


if __name__ == "__main__":
    gr_unittest.run(qa_leakage_canceller)
