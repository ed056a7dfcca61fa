#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: frame_sync finds a random frame offset exactly from the pilots at 10 dB, and on
noise alone tags nothing and counts its failed searches; a recording that starts mid-frame,
replayed with its tags through frame_sync, scores every whole frame against its own truth."""
import json
import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import analog, blocks, digital, gr, gr_unittest, sems
from gnuradio.sems.tag_file import tag_file_replay, tag_file_sink

MODELS = os.path.join(os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..", "..")),
                      "models")
MASK = os.path.join(MODELS, "delay_single", "mask.json")  # pilots over 31 subcarriers, Newman phases
QPSK = [(1 + 1j) / 2 ** 0.5, (-1 + 1j) / 2 ** 0.5, (-1 - 1j) / 2 ** 0.5, (1 - 1j) / 2 ** 0.5]


class qa_frame_sync(gr_unittest.TestCase):

    def transmit(self, frames, cp, seed, mask=MASK, data_power=1.0):
        """frames of mapper -> ofdm_tx samples (data QPSK), as a numpy array"""
        n, m = 32, 64
        src = digital.chunks_to_symbols_bc(QPSK, 1)
        bits = analog.random_uniform_source_b(0, 4, seed)
        mapper = sems.pilot_mapper(mask_file=mask, data_power=data_power)
        head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
        sink = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(bits, src, mapper, head, sems.ofdm_tx(m, cp), sink)
        tb.run()
        return np.array(sink.data(), dtype=np.complex64)

    def sync(self, x, cp, search_frames=4, mask=MASK):
        src = blocks.vector_source_c(x.tolist())
        fs = sems.frame_sync(mask_file=mask, cp_len=cp, search_frames=search_frames)
        sink = blocks.vector_sink_c()
        msgs = blocks.message_debug()
        tb = gr.top_block()
        tb.connect(src, fs, sink)
        tb.msg_connect(fs, sems.keys.sync_port, msgs, "store")
        tb.run()
        return fs, np.array(sink.data()), sink.tags(), msgs

    def test_001_random_offset_found_exactly_at_10_db(self):
        cp = 48
        rng = np.random.default_rng(4)
        for trial in range(5):
            with self.subTest(trial=trial):
                frames = 6
                tx = self.transmit(frames, cp, seed=trial + 1)
                L = 32 * (64 + cp)
                offset = int(rng.integers(0, 3 * L))
                sigma2 = 10 ** (-10 / 10)  # 10 dB per sample (= per resource element)
                g = np.exp(1j * rng.uniform(0, 2 * np.pi)) * 0.8  # unknown gain and phase
                lead = np.zeros(offset, np.complex64)
                rx = np.concatenate([lead, g * tx])
                rx = rx + (rng.standard_normal(rx.size) + 1j * rng.standard_normal(rx.size)) * math.sqrt(
                    sigma2 / 2) * 0.8
                fs, y, tags, msgs = self.sync(rx.astype(np.complex64), cp)
                self.assertTrue(fs.locked())
                self.assertEqual(fs.offset(), offset)
                # the output starts at the frame: it is the transmitted stream (plus noise)
                self.assertLess(np.mean(np.abs(y[:L] / g - tx[:L]) ** 2), 2 * sigma2)
                key = pmt.intern(sems.keys.frame_tag)
                got = [(t.offset, pmt.to_uint64(t.value)) for t in tags if pmt.eqv(t.key, key)]
                self.assertEqual(got, [(f * L, f) for f in range(len(y) // L + (len(y) % L > 0))])
                self.assertEqual(msgs.num_messages(), 1)
                lock = msgs.get_message(0)
                self.assertEqual(pmt.to_long(pmt.dict_ref(lock, pmt.intern(sems.keys.sync_offset), pmt.PMT_NIL)), offset)
                self.assertGreater(fs.metric(), 25.0)

    def test_001b_pilot_energies_in_the_template(self):
        # A mask whose pilots differ in energy: frame_sync's template carries sqrt(p_k)·s_p as
        # the mapper sends it, so it finds the offset exactly and correlates better than a
        # template of equal energies would.
        cp = 48
        mask = sems.pilot_mask.load(MASK)
        power = [0.2 if k % 2 else 1.8 for k in range(mask.size())]
        if mask.size() % 2:
            power[-1] = 1.0
        rng = np.random.default_rng(7)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "power.json")
            sems.pilot_mask(mask.n_symbols(), mask.n_subcarriers(), mask.positions(), mask.pilot_symbol(),
                            power, mask.phases()).save(path)
            tx = self.transmit(6, cp, seed=3, mask=path)
            offset = 1234
            rx = np.concatenate([np.zeros(offset, np.complex64), tx])
            rx = rx + (rng.standard_normal(rx.size) + 1j * rng.standard_normal(rx.size)) * math.sqrt(0.1 / 2)
            rx = rx.astype(np.complex64)
            matched, _, _, _ = self.sync(rx, cp, mask=path)
            equal, _, _, _ = self.sync(rx, cp)
        self.assertTrue(matched.locked())
        self.assertEqual(matched.offset(), offset)
        self.assertGreater(matched.metric(), equal.metric())

    def test_001d_pilot_phases_in_the_template(self):
        # The shipped delay mask gives its 32 pilots on symbol 16 Newman phases. Through the
        # mapper and ofdm_tx (data off) that symbol peaks at 2.23 times its rms instead of
        # sqrt(32) = 5.66 (pilot_mask.h), and frame_sync, whose template carries the phases as
        # the mapper sends them, finds the offset exactly at 10 dB; the same mask without the
        # phases is a template that no longer matches the signal.
        cp = 48
        n, m = 32, 64
        mask = sems.pilot_mask.load(MASK)
        self.assertEqual(mask.phase_sequence(), "newman")
        rng = np.random.default_rng(5)
        with tempfile.TemporaryDirectory() as d:
            plain = os.path.join(d, "plain.json")
            mask.with_phases("zero").save(plain)
            for path, crest in ((MASK, 2.23), (plain, math.sqrt(32))):
                x = self.transmit(1, cp, seed=2, mask=path, data_power=0.0)
                sym = x.reshape(n, m + cp)[16, cp:]  # the pilot symbol, without its prefix
                self.assertAlmostEqual(np.abs(sym).max() / np.sqrt(np.mean(np.abs(sym) ** 2)), crest, delta=0.005)
            tx = self.transmit(6, cp, seed=4)
            offset = 2345
            rx = np.concatenate([np.zeros(offset, np.complex64), tx])
            rx = rx + (rng.standard_normal(rx.size) + 1j * rng.standard_normal(rx.size)) * math.sqrt(0.1 / 2)
            rx = rx.astype(np.complex64)
            matched, _, _, _ = self.sync(rx, cp)
            mismatched, _, _, _ = self.sync(rx, cp, mask=plain)
        self.assertTrue(matched.locked())
        self.assertEqual(matched.offset(), offset)
        self.assertGreater(matched.metric(), 25.0)
        self.assertLess(mismatched.metric(), matched.metric() / 2)

    def test_001c_zero_db_with_and_without_leakage(self):
        # 0 dB per resource element, a random start in noise. The echo (delay 23 samples, its
        # phase new every frame: a moving target) alone is timed at its own delay by the
        # non-coherent search (threshold 30.2: 1e-6 false locks per frame, frame_search.h);
        # with the transmitter's leakage 40 dB over it (delay 0), the coherent search times
        # the frame itself.
        cp, delay = 16, 23
        L = 32 * (64 + cp)
        rng = np.random.default_rng(11)
        for trial in range(3):
            tx = self.transmit(7, cp, seed=trial + 20)
            offset = int(rng.integers(0, 2 * L))
            echo = np.zeros(offset + delay + tx.size, np.complex64)
            for f in range(7):
                echo[offset + delay + f * L:offset + delay + (f + 1) * L] = tx[f * L:(f + 1) * L] * np.exp(
                    2j * np.pi * rng.uniform())
            noise = (rng.standard_normal(echo.size) + 1j * rng.standard_normal(echo.size)) / math.sqrt(2)
            leakage = np.zeros_like(echo)
            leakage[offset:offset + tx.size] = 100 * tx
            for name, rx, kw, expect in (("echo alone", echo + noise, dict(noncoherent=True, threshold=30.2),
                                          offset + delay),
                                         ("leakage", echo + noise + leakage, {}, offset)):
                with self.subTest(trial=trial, case=name):
                    src = blocks.vector_source_c(rx.astype(np.complex64).tolist())
                    fs = sems.frame_sync(mask_file=MASK, cp_len=cp, **kw)
                    tb = gr.top_block()
                    tb.connect(src, fs, blocks.null_sink(gr.sizeof_gr_complex))
                    tb.run()
                    self.assertTrue(fs.locked())
                    self.assertEqual(fs.offset() % L, expect % L)

    def test_002_noise_alone_no_tag_and_a_count(self):
        cp = 48
        L = 32 * (64 + cp)
        rng = np.random.default_rng(9)
        x = ((rng.standard_normal(12 * L) + 1j * rng.standard_normal(12 * L)) / math.sqrt(2)).astype(np.complex64)
        fs, y, tags, msgs = self.sync(x, cp)
        self.assertFalse(fs.locked())
        self.assertEqual(fs.offset(), -1)
        self.assertEqual(len(y), 0)
        self.assertEqual(len(tags), 0)
        self.assertEqual(msgs.num_messages(), 0)
        self.assertEqual(fs.failures(), 12 - 4)  # windows of 5 frames sliding by one over 12 frames
        self.assertLess(fs.metric(), 25.0)

    def test_002b_other_cyclic_prefix_refused(self):
        # Samples of a CP-16 transmitter with their frame tags, synchronised with CP 48: the
        # tags' spacing gives the transmitter's prefix away, the block stops and names both.
        n, m = 32, 64
        key = pmt.intern(sems.keys.frame_tag)
        x = self.transmit(6, 16, seed=3)
        tags = [gr.tag_utils.python_to_tag((f * n * (m + 16), key, pmt.from_uint64(f))) for f in range(6)]
        src = blocks.vector_source_c(x.tolist(), tags=tags)
        fs = sems.frame_sync(mask_file=MASK, cp_len=48)
        sink = blocks.vector_sink_c()
        tb = gr.top_block()
        tb.connect(src, fs, sink)
        tb.run()
        self.assertIn("transmitter's cyclic prefix is 16 samples, this block's cp_len is 48", fs.stream_error())
        self.assertEqual(len(sink.data()), 0)

    def test_003_bad_parameters(self):
        for kw, needle in ((dict(mask_file=MASK, cp_len=-1), "cp_len"),
                           (dict(mask_file=MASK, search_frames=0), "frames"),
                           (dict(mask_file=MASK, pilot_power=0.0), "pilot_power"),
                           (dict(mask_file=MASK, threshold=float("nan")), "threshold"),
                           (dict(), "no pilots"),
                           # 32 pilots on one subcarrier: a tone, periodic in samples
                           (dict(mask_file=os.path.join(MODELS, "classifier", "mask.json")), "cannot locate")):
            with self.subTest(needle=needle):
                with self.assertRaisesRegex(ValueError, "frame_sync.*" + needle):
                    sems.frame_sync(**kw)

    def test_004_replay_mid_frame_scores_every_whole_frame(self):
        """record (target_channel_td plus the direct path, drop a random number of samples),
        replay file_source -> tag_file_replay -> frame_sync -> ofdm_rx -> extractor -> delay
        sink: frame_sync drops the replayed sems_frame tags, numbers the frames it finds, and
        carries each sems_truth to the same sample, so frame k of the sync is recorded frame
        k + first, where first = (offset found + samples dropped) / L."""
        n, m, cp, frames = 32, 64, 16, 10
        L = n * (m + cp)
        bundle = os.path.join(MODELS, "delay_single")
        with open(os.path.join(bundle, "bundle.json")) as f:
            scene = json.dumps(json.load(f)["training"]["scene"])
        frame_key, truth_key = pmt.intern(sems.keys.frame_tag), pmt.intern(sems.keys.truth_tag)
        rng = np.random.default_rng(12)
        with tempfile.TemporaryDirectory() as tmp:
            for trial in range(3):
                skip = int(rng.integers(1, 2 * L))
                with self.subTest(trial=trial, skip=skip):
                    path = os.path.join(tmp, "rec%d.c64" % trial)
                    tb = gr.top_block()
                    mapper = sems.pilot_mapper(mask_file=MASK)
                    head = blocks.head(gr.sizeof_gr_complex * m, frames * n)
                    tx = sems.ofdm_tx(m, cp)
                    channel = sems.target_channel_td(scene=scene, snr_db=10.0, seed=trial + 1, cp_len=cp)
                    # the direct path (TX leakage, 6 dB below the echo): the coherent part
                    # frame_sync locks to; the echo's delay and Doppler change every frame
                    direct = blocks.multiply_const_cc(0.5)
                    rx = blocks.add_cc()
                    drop = blocks.skiphead(gr.sizeof_gr_complex, skip)  # shifts the tags too
                    samples = blocks.file_sink(gr.sizeof_gr_complex, path)
                    tags = tag_file_sink(path + ".tags")
                    tb.connect(analog.random_uniform_source_b(0, 4, trial + 1),
                               digital.chunks_to_symbols_bc(QPSK, 1), mapper, head, tx, channel, (rx, 0))
                    tb.connect(tx, direct, (rx, 1))
                    tb.connect(rx, drop, samples)
                    tb.connect(drop, tags)
                    tb.run()
                    samples.close()

                    tb = gr.top_block()
                    replay = tag_file_replay(path + ".tags")
                    fs = sems.frame_sync(mask_file=MASK, cp_len=cp)
                    seen = blocks.vector_sink_c()
                    sink = sems.delay_estimator_sink(bundle, 32, 1, 1, 0)
                    tb.connect(blocks.file_source(gr.sizeof_gr_complex, path), replay, fs, seen)
                    tb.connect(fs, sems.ofdm_rx(m, cp), sems.pilot_extractor(mask_file=MASK), sink)
                    tb.run()

                    self.assertTrue(fs.locked())
                    self.assertEqual((fs.offset() + skip) % L, 0, "the lock is on a recorded frame start")
                    first = (fs.offset() + skip) // L
                    whole = frames - first
                    self.assertGreater(whole, frames // 2)
                    got = seen.tags()
                    sync = sorted((t.offset, pmt.to_uint64(t.value)) for t in got if pmt.eqv(t.key, frame_key))
                    truth = sorted((t.offset, pmt.to_uint64(pmt.dict_ref(t.value, pmt.intern(sems.keys.frame),
                                                                         pmt.PMT_NIL)))
                                   for t in got if pmt.eqv(t.key, truth_key))
                    self.assertEqual(sync, [(k * L, k) for k in range(whole)])  # no replayed frame tag
                    self.assertEqual(truth, [(k * L, k + first) for k in range(whole)])
                    self.assertEqual(sink.frames(), whole)
                    self.assertEqual(sink.frames_scored(), whole)
                    self.assertEqual(sink.frames_skipped(), 0)


if __name__ == "__main__":
    gr_unittest.run(qa_frame_sync)
