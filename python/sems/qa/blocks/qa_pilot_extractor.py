#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: pilot_extractor, alone and at the end of the noiseless chain
pilot_mapper -> target_channel -> pilot_extractor (docs/design.md §2, §3)."""
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

N, M = 4, 8
B = M * 468.75e3  # keeps the default subcarrier spacing (and so the 320 m unambiguous range)
POS = [0, 3, 9, 17, 31]  # flat n*M+m, deliberately not sorted by row inside the frame
SP = 0.6 - 0.8j
EP, ED = 2.5, 0.5
SEED = 11


def settings():
    return sems.frame_settings(n_symbols=N, n_subcarriers=M, bandwidth_hz=B, cp_len=0)


def expected_h(frames, seed=SEED, scene=None):
    """Noiseless H of `frames` consecutive frames from a same-seed channel model."""
    cm = sems.channel_model(settings(), scene if scene is not None else sems.scene.random(), seed)
    return cm.generate(frames)


class drip(gr.basic_block):
    """Passes at most `chunk` vectors per call (or a random 1..chunk with a seed), so
    the next block sees small pieces."""

    def __init__(self, vlen, chunk, seed=None):
        gr.basic_block.__init__(self, "drip", in_sig=[(np.complex64, vlen)], out_sig=[(np.complex64, vlen)])
        self.chunk = chunk
        self.rng = np.random.default_rng(seed) if seed is not None else None

    def general_work(self, input_items, output_items):
        limit = self.chunk if self.rng is None else int(self.rng.integers(1, self.chunk + 1))
        n = min(limit, len(input_items[0]), len(output_items[0]))
        output_items[0][:n] = input_items[0][:n]
        self.consume(0, n)
        return n


def tags_by_key(sink):
    out = {}
    for t in sink.tags():
        out.setdefault(pmt.symbol_to_string(t.key), []).append((t.offset, pmt.to_python(t.value)))
    return out


def random_data(count, seed=1, scale=1.0):
    rng = np.random.default_rng(seed)
    return (scale * (rng.standard_normal(count) + 1j * rng.standard_normal(count))).astype(np.complex64)


class qa_pilot_extractor(gr_unittest.TestCase):

    def chain(self, frames, chunk=None, skip_before_channel=0, skip_before_extractor=0, pos=POS,
              pilot_power=EP, data_power=ED, snr_db=float("inf"), data_scale=1.0, mask_file=""):
        """Runs the chain and returns (observations, tags, extractor, channel)."""
        tb = gr.top_block()
        n_data = frames * (N * M - len(pos))
        where = dict(mask_file=mask_file) if mask_file else dict(pilot_positions=pos)
        mapper = sems.pilot_mapper(**where, n_symbols=N, n_subcarriers=M, pilot_symbol=SP,
                                   pilot_power=pilot_power, data_power=data_power)
        channel = sems.target_channel(snr_db=snr_db, seed=SEED, n_symbols=N, n_subcarriers=M, bandwidth_hz=B)
        extractor = sems.pilot_extractor(**where, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
        sink = blocks.vector_sink_c(len(pos))
        chain = []
        if n_data:
            chain = [blocks.vector_source_c(random_data(n_data, scale=data_scale).tolist())]
        else:  # pilots only: the mapper is a source
            chain = []
        chain.append(mapper)
        if not n_data:
            chain.append(blocks.head(gr.sizeof_gr_complex * M, frames * N))
        if skip_before_channel:
            chain.append(blocks.skiphead(gr.sizeof_gr_complex * M, skip_before_channel))
        chain.append(channel)
        if skip_before_extractor:
            chain.append(blocks.skiphead(gr.sizeof_gr_complex * M, skip_before_extractor))
        if chunk:
            chain.append(drip(M, chunk))
            for b in (mapper, channel, chain[-1]):
                b.set_max_noutput_items(chunk)
        chain += [extractor, sink]
        tb.connect(*chain)
        tb.run()
        obs = np.array(sink.data(), dtype=np.complex64).reshape(-1, len(pos))
        return obs, tags_by_key(sink), extractor, channel

    def check_frames(self, obs, tags, first_frame, frames, h=None, truths=None, pos=POS, ep=EP):
        if h is None:
            h, truths = expected_h(frames)
        want = np.sqrt(ep) * h.reshape(frames, -1)[first_frame:, sorted(pos)]
        self.assertEqual(obs.shape, want.shape)
        np.testing.assert_allclose(obs, want, rtol=1e-5, atol=1e-6 * np.sqrt(ep))
        # One frame tag and one truth tag per output item, with the exact frame index.
        n_out = frames - first_frame
        self.assertEqual(tags[sems.keys.frame_tag], [(i, first_frame + i) for i in range(n_out)])
        truth = tags[sems.keys.truth_tag]
        self.assertEqual([o for o, _ in truth], list(range(n_out)))
        for i, (_, d) in enumerate(truth):
            want_t = truths[first_frame + i]
            self.assertEqual(d[sems.keys.frame], first_frame + i)
            self.assertEqual(d[sems.keys.class_name], want_t[sems.keys.class_name])
            self.assertEqual(d[sems.keys.class_id], want_t[sems.keys.class_id])
            self.assertAlmostEqual(d[sems.keys.delay_s], want_t[sems.keys.delay_s], delta=1e-15)
            self.assertAlmostEqual(d[sems.keys.velocity_mps], want_t[sems.keys.velocity_mps], delta=1e-12)

    def test_001_noiseless_chain_exact(self):
        frames = 6
        obs, tags, ex, ch = self.chain(frames)
        self.check_frames(obs, tags, 0, frames)
        self.assertEqual((ex.frames_out(), ex.frames_dropped_partial(), ex.frames_skipped_nonfinite()),
                         (frames, 0, 0))
        self.assertEqual(ch.frames(), frames)

    def test_002_any_chunk_size(self):
        frames = 5
        h, truths = expected_h(frames)
        for chunk in (1, 2, 3, N - 1, N + 1, 2 * N + 1, 1000):
            with self.subTest(chunk=chunk):
                obs, tags, ex, _ = self.chain(frames, chunk=chunk)
                self.check_frames(obs, tags, 0, frames, h, truths)
                self.assertEqual(ex.frames_dropped_partial(), 0)

    def test_003_stream_starts_mid_frame_at_extractor(self):
        # The extractor's stream begins 1.5 frames in: the half frame is dropped and
        # counted, frames 2.. come out exactly.
        frames = 6
        h, truths = expected_h(frames)
        for chunk in (None, 1, 3):
            with self.subTest(chunk=chunk):
                obs, tags, ex, _ = self.chain(frames, chunk=chunk, skip_before_extractor=N + N // 2)
                self.check_frames(obs, tags, 2, frames, h, truths)
                self.assertEqual(ex.frames_dropped_partial(), 1)
                self.assertEqual(ex.frames_out(), frames - 2)

    def test_004_stream_starts_mid_frame_at_channel(self):
        # The channel sees a partial frame 0 (it draws a realization for it, as
        # generate() does for frame 0), then aligns to the tag of frame 1.
        frames = 5
        h, truths = expected_h(frames)
        for chunk in (None, 1):
            with self.subTest(chunk=chunk):
                obs, tags, ex, ch = self.chain(frames, chunk=chunk, skip_before_channel=1)
                self.check_frames(obs, tags, 1, frames, h, truths)
                self.assertEqual(ex.frames_dropped_partial(), 1)
                self.assertEqual(ch.frames(), frames)

    def test_005_one_pilot_and_all_pilots(self):
        for pos in ([13], list(range(N * M))):
            with self.subTest(n_pilots=len(pos)):
                frames = 3
                obs, tags, ex, _ = self.chain(frames, pos=pos)
                self.check_frames(obs, tags, 0, frames, pos=pos)

    def test_006_amplitude_extremes(self):
        # Pilot amplitudes sqrt(E_p) of 1e-20 and 1e20, data of the same scale.
        frames = 3
        h, truths = expected_h(frames)
        for amp in (1e-20, 1e20):
            with self.subTest(amplitude=amp):
                obs, tags, _, _ = self.chain(frames, pilot_power=amp * amp, data_scale=amp)
                self.assertTrue(np.all(np.isfinite(obs)))
                want = amp * h.reshape(frames, -1)[:, sorted(POS)]
                np.testing.assert_allclose(obs / amp, want / amp, rtol=1e-5, atol=1e-6)

    def test_007_snr_extremes(self):
        frames = 4
        h, _ = expected_h(frames)
        clean = np.sqrt(EP) * h.reshape(frames, -1)[:, sorted(POS)]
        obs, _, _, _ = self.chain(frames, snr_db=300.0)
        np.testing.assert_allclose(obs, clean, rtol=1e-5, atol=1e-6)
        obs, _, ex, _ = self.chain(frames, snr_db=-50.0)
        self.assertTrue(np.all(np.isfinite(obs)))
        self.assertEqual(ex.frames_out(), frames)
        noise = obs - clean  # sigma^2 = 1e5: far above the signal, and finite
        self.assertGreater(np.mean(np.abs(noise) ** 2), 1e4)

    def test_008_untagged_stream_is_counted(self):
        frames = 3
        x = random_data(frames * N * M, seed=3).reshape(-1, M)
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=M)
        ex = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
        sink = blocks.vector_sink_c(len(POS))
        tb = gr.top_block()
        tb.connect(src, ex, sink)
        tb.run()
        obs = np.array(sink.data()).reshape(-1, len(POS))
        want = x.reshape(frames, -1)[:, sorted(POS)] / np.complex64(SP)
        np.testing.assert_allclose(obs, want, rtol=1e-6)
        self.assertEqual(tags_by_key(sink)[sems.keys.frame_tag], [(i, i) for i in range(frames)])

    def test_009_nonfinite_frame_skipped(self):
        frames = 4
        x = random_data(frames * N * M, seed=4).reshape(frames, N, M)
        x[1, 2, 5] = np.nan  # a data element, not a pilot: the frame is still bad
        x[2, 0, 0] = np.inf
        tags = [gr.tag_utils.python_to_tag((f * N, pmt.intern(sems.keys.frame_tag), pmt.from_uint64(10 + f)))
                for f in range(frames)]
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=M, tags=tags)
        ex = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
        sink = blocks.vector_sink_c(len(POS))
        tb = gr.top_block()
        tb.connect(src, ex, sink)
        tb.run()
        self.assertEqual((ex.frames_out(), ex.frames_skipped_nonfinite()), (2, 2))
        obs = np.array(sink.data()).reshape(-1, len(POS))
        self.assertTrue(np.all(np.isfinite(obs)))
        self.assertEqual(tags_by_key(sink)[sems.keys.frame_tag], [(0, 10), (1, 13)])

    def test_010_short_frame_between_tags_dropped(self):
        # Frame 1 is cut short by the tag of frame 2, frame 4 by the end of the
        # stream: both dropped and counted.
        lengths = [N, N - 1, N, N, 2]
        rows = sum(lengths)
        x = random_data(rows * M, seed=5).reshape(rows, M)
        tags, offset = [], 0
        for f, n in enumerate(lengths):
            tags.append(gr.tag_utils.python_to_tag((offset, pmt.intern(sems.keys.frame_tag), pmt.from_uint64(f))))
            offset += n
        src = blocks.vector_source_c(x.ravel().tolist(), vlen=M, tags=tags)
        ex = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
        sink = blocks.vector_sink_c(len(POS))
        tb = gr.top_block()
        tb.connect(src, ex, sink)
        tb.run()
        self.assertEqual((ex.frames_out(), ex.frames_dropped_partial()), (3, 2))
        self.assertEqual([v for _, v in tags_by_key(sink)[sems.keys.frame_tag]], [0, 2, 3])

    def test_011_random_segments_and_chunks(self):
        # Frames of random length (short, whole, long), some untagged, NaNs here and
        # there, delivered in random pieces: the counters and every output item must
        # match a plain reference of the rules.
        rng = np.random.default_rng(7)
        lengths = rng.choice([1, N - 1, N, N, N, N + 2, 2 * N], size=40)
        tagged = rng.random(40) < 0.8
        rows = int(lengths.sum())
        x = random_data(rows * M, seed=8).reshape(rows, M)
        bad_rows = rng.choice(rows, size=4, replace=False)
        x[bad_rows, rng.integers(0, M, size=4)] = np.nan
        tags, starts, offset = [], {}, 0
        for f, (n, t) in enumerate(zip(lengths, tagged)):
            if t:
                tags.append(gr.tag_utils.python_to_tag((offset, pmt.intern(sems.keys.frame_tag),
                                                        pmt.from_uint64(1000 + f))))
                starts[offset] = 1000 + f
            offset += int(n)

        # Reference: the rules of pilot_extractor.h, item by item.
        want, want_frames, dropped, skipped = [], [], 0, 0
        row, frame, started, bad, grid = 0, 0, False, False, []
        for i in range(rows):
            if i in starts:
                dropped += row > 0
                row, frame, started, bad, grid = 0, starts[i], True, False, []
            elif row == 0:
                frame, started, bad, grid = (frame + 1 if started else 0), True, False, []
            bad |= not np.all(np.isfinite(x[i]))
            grid.append(x[i])
            row += 1
            if row == N:
                if bad:
                    skipped += 1
                else:
                    want.append(np.concatenate(grid)[sorted(POS)] / np.complex64(SP))
                    want_frames.append(frame)
                row = 0
        dropped += row > 0

        for chunk in (1, 3, 2 * N + 1):
            with self.subTest(chunk=chunk):
                src = blocks.vector_source_c(x.ravel().tolist(), vlen=M, tags=tags)
                pieces = drip(M, chunk, seed=chunk)
                pieces.set_max_noutput_items(chunk)
                ex = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
                sink = blocks.vector_sink_c(len(POS))
                tb = gr.top_block()
                tb.connect(src, pieces, ex, sink)
                tb.run()
                obs = np.array(sink.data(), dtype=np.complex64).reshape(-1, len(POS))
                np.testing.assert_allclose(obs, np.array(want), rtol=1e-6)
                self.assertEqual([v for _, v in tags_by_key(sink)[sems.keys.frame_tag]], want_frames)
                self.assertEqual((ex.frames_out(), ex.frames_dropped_partial(), ex.frames_skipped_nonfinite()),
                                 (len(want), dropped, skipped))

    def test_012_bad_masks_refused(self):
        def refuses(text, **kw):
            args = dict(pilot_positions=POS, n_symbols=N, n_subcarriers=M)
            args.update(kw)
            with self.assertRaises(ValueError) as cm:
                sems.pilot_extractor(**args)
            self.assertIn(text, str(cm.exception))
            self.assertIn("pilot_extractor", str(cm.exception))

        refuses("duplicate", pilot_positions=[1, 5, 1])
        refuses("outside", pilot_positions=[0, N * M])
        refuses("outside", pilot_positions=[-1])
        refuses("no pilots", pilot_positions=[])
        refuses("pilot_symbol", pilot_symbol=0j)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "mask.json")
            sems.pilot_mask(N + 1, M, [(0, 1), (2, 3)]).save(path)
            refuses("is 5 x 8 but the frame is 4 x 8", pilot_positions=[], mask_file=path)
            refuses("not both", mask_file=path)
            refuses("mask.json", pilot_positions=[], mask_file=os.path.join(d, "missing", "mask.json"))

    def test_013_every_mask_block_names_the_grid_fields_that_differ(self):
        """A mask file carries its grid N x M: the extractor, the mapper, frame sync and the
        range-Doppler map refuse a file of another grid, naming each field that differs and both
        values (pilot_mask::check_frame, the one comparison)."""
        makers = {"pilot_extractor": sems.pilot_extractor, "pilot_mapper": sems.pilot_mapper,
                  "frame_sync": sems.frame_sync, "range_doppler_map": sems.range_doppler_map}
        with tempfile.TemporaryDirectory() as d:
            for grid, fields in (((N, 2 * M), ["n_subcarriers: the mask has 16, the frame has 8"]),
                                 ((N + 1, 2 * M), ["n_symbols: the mask has 5, the frame has 4",
                                                   "n_subcarriers: the mask has 16, the frame has 8"])):
                path = os.path.join(d, "mask_%dx%d.json" % grid)
                sems.pilot_mask(grid[0], grid[1], [(0, 1), (1, 3), (2, 9), (3, 12)]).save(path)
                for name, make in makers.items():
                    with self.assertRaises(ValueError, msg=name) as cm:
                        make(mask_file=path, n_symbols=N, n_subcarriers=M)
                    for text in [name, path] + fields:
                        self.assertIn(text, str(cm.exception), name)

    def sent(self, path):
        """What the mapper of mask file `path` sends at its pilots in one frame, in mask order."""
        tb = gr.top_block()
        mapper = sems.pilot_mapper(mask_file=path, n_symbols=N, n_subcarriers=M, pilot_symbol=SP,
                                   pilot_power=EP, data_power=ED)
        sink = blocks.vector_sink_c(M)
        tb.connect(blocks.vector_source_c(random_data(N * M - len(POS)).tolist()), mapper, sink)
        tb.run()
        return np.array(sink.data()).reshape(-1)[sorted(POS)]

    def power_mask(self, d):
        """A mask file over POS whose pilots differ in energy (mean 1); returns (path, energies in mask order)."""
        power = [0.25, 2.0, 0.5, 1.25, 1.0]  # for POS as listed
        path = os.path.join(d, "power.json")
        sems.pilot_mask(N, M, [(p // M, p % M) for p in POS], SP, power).save(path)
        order = np.argsort(POS)
        return path, np.array(power)[order]

    def test_013_pilot_energies_noiseless_exact(self):
        # Pilot k is sent as sqrt(E_p·p_k)·s_p and divided by sqrt(p_k)·s_p: the extractor
        # returns sqrt(E_p)·H exactly as with equal power.
        frames = 5
        with tempfile.TemporaryDirectory() as d:
            path, _ = self.power_mask(d)
            obs, tags, ex, _ = self.chain(frames, mask_file=path)
            self.check_frames(obs, tags, 0, frames)
            # What the mapper sends: sqrt(E_p·p_k)·s_p at each pilot.
            mask = sems.pilot_mask.load(path)
            np.testing.assert_allclose(self.sent(path), np.sqrt(EP * np.array(mask.power())) * SP, rtol=1e-6)

    def test_014_pilot_noise_scales_with_energy(self):
        # Pilot k's observation noise has variance σ²/p_k (σ² = 1 at 0 dB, |s_p| = 1, E_p = 1):
        # measured over many frames, within a few per cent of the closed form.
        frames = 6000
        with tempfile.TemporaryDirectory() as d:
            path, power = self.power_mask(d)
            obs, _, _, _ = self.chain(frames, mask_file=path, snr_db=0.0, pilot_power=1.0)
        h, _ = expected_h(frames)
        noise = obs - h.reshape(frames, -1)[:, sorted(POS)]
        var = np.mean(np.abs(noise) ** 2, axis=0)
        sigma2 = sems.channel_model.noise_variance(0.0)
        np.testing.assert_allclose(var * power, sigma2, rtol=0.05)
        # The ratio of two pilots' variances is the inverse ratio of their energies (0.25 against 2: 8).
        k_lo, k_hi = int(np.argmin(power)), int(np.argmax(power))
        self.assertAlmostEqual(var[k_lo] / var[k_hi], power[k_hi] / power[k_lo], delta=0.05 * 8)

    def test_015_pilot_phases_noiseless_exact(self):
        # Pilot k is sent as sqrt(E_p·p_k)·s_p·exp(jφ_k) and divided by sqrt(p_k)·s_p·exp(jφ_k)
        # (pilot_mask.transmitted_pilot): the extractor returns sqrt(E_p)·H exactly, for an
        # explicit list with energies and for Newman phases; an extractor that ignored the
        # phases would return H·exp(jφ_k).
        frames = 5
        phases = [0.7, -2.0, 3.1, 1.3, -0.4]  # for POS as listed
        with tempfile.TemporaryDirectory() as d:
            listed = os.path.join(d, "phases.json")
            power = [0.25, 2.0, 0.5, 1.25, 1.0]
            sems.pilot_mask(N, M, [(p // M, p % M) for p in POS], SP, power, phases).save(listed)
            newman = os.path.join(d, "newman.json")
            sems.pilot_mask(N, M, [(p // M, p % M) for p in POS], SP).with_phases("newman").save(newman)
            for path in (listed, newman):
                with self.subTest(mask=os.path.basename(path)):
                    mask = sems.pilot_mask.load(path)
                    self.assertFalse(mask.zero_phases())
                    obs, tags, _, _ = self.chain(frames, mask_file=path)
                    self.check_frames(obs, tags, 0, frames)
                    # What the mapper sends: sqrt(E_p·p_k)·s_p·exp(jφ_k) at each pilot.
                    want = np.sqrt(EP * np.array(mask.power())) * SP * np.exp(1j * np.array(mask.phases()))
                    np.testing.assert_allclose(self.sent(path), want, rtol=1e-6)
            # The phases in mask order: those of POS as listed, sorted with their pilots.
            np.testing.assert_allclose(sems.pilot_mask.load(listed).phases(), np.array(phases)[np.argsort(POS)])
            # The mapper with the phases, an extractor without them: H·exp(jφ_k), not H.
            h, _ = expected_h(frames)
            tb = gr.top_block()
            n_data = frames * (N * M - len(POS))
            mapper = sems.pilot_mapper(mask_file=newman, n_symbols=N, n_subcarriers=M, pilot_symbol=SP,
                                       pilot_power=EP, data_power=ED)
            channel = sems.target_channel(snr_db=float("inf"), seed=SEED, n_symbols=N, n_subcarriers=M,
                                          bandwidth_hz=B)
            blind = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
            sink = blocks.vector_sink_c(len(POS))
            tb.connect(blocks.vector_source_c(random_data(n_data).tolist()), mapper, channel, blind, sink)
            tb.run()
            obs = np.array(sink.data()).reshape(frames, -1)
            rot = np.exp(1j * np.array(sems.pilot_mask.load(newman).phases()))
            np.testing.assert_allclose(obs, np.sqrt(EP) * h.reshape(frames, -1)[:, sorted(POS)] * rot,
                                       rtol=1e-5, atol=1e-6)

    def test_016_super_frame_masks(self):
        # A mask over a super-frame of 3 frames, each set its own 5 pilots (one with energies):
        # frame f carries set f mod 3 at the mapper and is read at the same set by the
        # extractor, for any chunk size; F = 1 of the same file format is the plain mask.
        frames = 7
        sets = [[0, 3, 9, 17, 31], [1, 2, 12, 20, 30], [5, 8, 16, 24, 27]]
        power = [0.5, 1.5, 1.0, 1.75, 0.25]
        masks = [sems.pilot_mask(N, M, [(p // M, p % M) for p in sets[0]], SP),
                 sems.pilot_mask(N, M, [(p // M, p % M) for p in sets[1]], SP, power),
                 sems.pilot_mask(N, M, [(p // M, p % M) for p in sets[2]], SP).with_phases("newman")]
        h, truths = expected_h(frames)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "super.json")
            sems.super_frame_mask(masks).save(path)
            self.assertEqual(sems.super_frame_mask.load(path).n_frames(), 3)
            for chunk in (None, 1, N + 1):
                with self.subTest(chunk=chunk):
                    obs, tags, ex, _ = self.chain(frames, chunk=chunk, pos=sets[0], mask_file=path)
                    want = np.array([np.sqrt(EP) * h[f].ravel()[sets[f % 3]] for f in range(frames)])
                    np.testing.assert_allclose(obs, want, rtol=1e-5, atol=1e-6)
                    self.assertEqual(tags[sems.keys.frame_tag], [(f, f) for f in range(frames)])
                    self.assertEqual(ex.super_frame().n_frames(), 3)
                    self.assertEqual(ex.n_pilots(), 5)
            # The extractor picks the set by the frame tag's index: frames 7 and 8 are sets 1 and 2.
            x = random_data(2 * N * M, seed=3).reshape(2 * N, M)
            key = pmt.intern(sems.keys.frame_tag)
            tags = [gr.tag_utils.python_to_tag((0, key, pmt.from_uint64(7))),
                    gr.tag_utils.python_to_tag((N, key, pmt.from_uint64(8)))]
            ex = sems.pilot_extractor(mask_file=path, n_symbols=N, n_subcarriers=M, pilot_symbol=SP)
            sink = blocks.vector_sink_c(5)
            tb = gr.top_block()
            tb.connect(blocks.vector_source_c(x.ravel().tolist(), vlen=M, tags=tags), ex, sink)
            tb.run()
            obs = np.array(sink.data()).reshape(2, 5)
            for row, f in enumerate((7, 8)):
                mask = masks[f % 3]
                sent = np.array([mask.transmitted_pilot(k) for k in range(5)])
                np.testing.assert_allclose(obs[row], x[row * N:(row + 1) * N].ravel()[sets[f % 3]] / sent, rtol=1e-6)
            # Blocks that read one frame's pilots refuse a super-frame, naming its F.
            plain = os.path.join(d, "plain_symbol.json")
            sems.super_frame_mask([sems.pilot_mask(N, M, [(p // M, p % M) for p in s]) for s in sets]).save(plain)
            for make in (sems.frame_sync, sems.range_doppler_map):
                with self.assertRaises(ValueError) as cm:
                    make(mask_file=plain, n_symbols=N, n_subcarriers=M)
                self.assertIn("super-frame of F = 3", str(cm.exception))
            # The plain mask reader names what the file is.
            with self.assertRaises(ValueError) as cm:
                sems.pilot_mask.load(path)
            self.assertIn("super_frame_mask", str(cm.exception))


if __name__ == "__main__":
    gr_unittest.run(qa_pilot_extractor)
