#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: target_channel, the frequency-domain emulator block (docs/design.md §1, §3).
The channel physics is tested in C++ (lib/qa_*.cc); here: the block's adapter work —
same frames as channel_model, frame alignment, truth tags, SNR, counters, bad input."""
import json
import math
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

N, M = 4, 8
B = M * 468.75e3  # the default subcarrier spacing, so the class ranges fit
SEED = 5
FRAME = pmt.intern(sems.keys.frame_tag)


def settings():
    return sems.frame_settings(n_symbols=N, n_subcarriers=M, bandwidth_hz=B, cp_len=0)


def fixed_scene():
    """Three paths, micro-Doppler, two targets: every term of H at once."""
    drone = sems.target_spec(sems.target_class.drone, 60.0, 7.0, sems.micro_doppler(100.0, 0.01, 0.3),
                             1.0, [sems.path_spec(0.0, 1.0), sems.path_spec(12.0, 0.5)])
    car = sems.target_spec(sems.target_class.car, 150.0, -15.0)
    return sems.scene.fixed([drone, car], target_of_interest=0)


def channel(scene="", **kw):
    args = dict(seed=SEED, n_symbols=N, n_subcarriers=M, bandwidth_hz=B)
    args.update(kw)
    return sems.target_channel(scene, **args)


def random_symbols(rows, seed=2, scale=1.0):
    rng = np.random.default_rng(seed)
    return (scale * (rng.standard_normal((rows, M)) + 1j * rng.standard_normal((rows, M)))).astype(np.complex64)


def run(block, x, tags=(), chunk=None):
    src = blocks.vector_source_c(x.ravel().tolist(), vlen=M, tags=list(tags))
    sink = blocks.vector_sink_c(M)
    if chunk:  # (a vector_source with tags must not be limited: GNU Radio 3.10.5 stalls)
        block.set_max_noutput_items(chunk)
    tb = gr.top_block()
    tb.connect(src, block, sink)
    tb.run()
    return np.array(sink.data(), dtype=np.complex64).reshape(-1, M), sink.tags()


def run_streams(block, x, n_receive):
    """One input, one sink per output: every output's symbols and tags."""
    src = blocks.vector_source_c(x.ravel().tolist(), vlen=M)
    sinks = [blocks.vector_sink_c(M) for _ in range(n_receive)]
    tb = gr.top_block()
    tb.connect(src, block)
    for k, sink in enumerate(sinks):
        tb.connect((block, k), sink)
    tb.run()
    return [np.array(s.data(), dtype=np.complex64).reshape(-1, M) for s in sinks], [s.tags() for s in sinks]


def truth_tags(tags):
    return [(t.offset, pmt.to_python(t.value)) for t in tags if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]


def frame_tag(offset, frame):
    return gr.tag_utils.python_to_tag((offset, FRAME, pmt.from_uint64(frame)))


class qa_target_channel(gr_unittest.TestCase):

    def test_001_fixed_scene_same_frames_as_model(self):
        frames = 5
        sc = fixed_scene()
        x = random_symbols(frames * N)
        y, tags = run(channel(sc.to_json_string()), x)
        h, truths = sems.channel_model(settings(), sc, SEED).generate(frames)
        np.testing.assert_allclose(y, h.reshape(-1, M) * x, rtol=1e-5, atol=1e-6)
        truth = truth_tags(tags)
        self.assertEqual([o for o, _ in truth], [f * N for f in range(frames)])
        for f, (_, d) in enumerate(truth):
            self.assertEqual(d[sems.keys.frame], f)
            self.assertEqual(d[sems.keys.class_name], "drone")
            self.assertEqual(d[sems.keys.n_paths], 3)
            self.assertEqual(d[sems.keys.snr_db], math.inf)
            self.assertEqual(d[sems.keys.micro_motion], truths[f][sems.keys.micro_motion])
            self.assertIsNone(d[sems.keys.micro_motion_params])  # no scatterer body
            self.assertEqual(d[sems.keys.class_library], "paper")
            for key in (sems.keys.delay_s, sems.keys.delay_index, sems.keys.range_m, sems.keys.velocity_mps):
                self.assertAlmostEqual(d[key], truths[f][key], delta=1e-12 * max(1.0, abs(truths[f][key])))

    def test_002_scene_file_equals_json(self):
        frames = 2
        x = random_symbols(frames * N)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "scene.json")
            fixed_scene().save(path)
            y_file, _ = run(channel(path), x)
        y_json, _ = run(channel(fixed_scene().to_json_string()), x)
        np.testing.assert_array_equal(y_file, y_json)

    def test_003_frame_index_from_tags(self):
        # Tags name frames 100, 101, ...: the slow time starts at 100·N and the truth
        # says 100; the draws are the model's first two.
        sc = fixed_scene()
        x = random_symbols(2 * N)
        y, tags = run(channel(sc.to_json_string()), x, [frame_tag(0, 100), frame_tag(N, 101)])
        cm = sems.channel_model(settings(), sc, SEED)
        h = np.concatenate([cm.channel(cm.draw(f), f * N) for f in (100, 101)])
        np.testing.assert_allclose(y, h * x, rtol=1e-5, atol=1e-6)
        self.assertEqual([d[sems.keys.frame] for _, d in truth_tags(tags)], [100, 101])
        # A tag in mid-frame starts a new frame there.
        y, tags = run(channel(sc.to_json_string()), random_symbols(2 * N), [frame_tag(0, 0), frame_tag(N - 1, 1)])
        self.assertEqual([(o, d[sems.keys.frame]) for o, d in truth_tags(tags)], [(0, 0), (N - 1, 1), (2 * N - 1, 2)])

    def test_004_random_scene_options(self):
        frames = 6
        _, tags = run(channel(classes=["car"], paths_per_target=3, clutter_paths=2, clutter_csr_db=-10.0),
                      random_symbols(frames * N))
        truth = truth_tags(tags)
        self.assertEqual(len(truth), frames)
        for _, d in truth:
            self.assertEqual(d[sems.keys.class_name], "car")
            self.assertEqual(d[sems.keys.n_paths], 5)
        # Same seed, same frames as the model with the same random scene.
        x = random_symbols(frames * N)
        y, _ = run(channel(classes=["pedestrian", "drone"], micro_doppler=False), x)
        spec = sems.random_spec(classes=[sems.target_class.pedestrian, sems.target_class.drone], micro_doppler=False)
        h, _ = sems.channel_model(settings(), sems.scene.random(spec), SEED).generate(frames)
        np.testing.assert_allclose(y, h.reshape(-1, M) * x, rtol=1e-5, atol=1e-6)
        # heading="any": the model's frames with that heading, both signs of velocity.
        frames = 40
        x = random_symbols(frames * N)
        y, tags = run(channel(classes=["car"], heading="any"), x)
        spec = sems.random_spec(classes=[sems.target_class.car], heading=sems.heading_kind.any)
        h, truths = sems.channel_model(settings(), sems.scene.random(spec), SEED).generate(frames)
        np.testing.assert_allclose(y, h.reshape(-1, M) * x, rtol=1e-5, atol=1e-6)
        v = [d[sems.keys.velocity_mps] for _, d in truth_tags(tags)]
        self.assertEqual(v, [t[sems.keys.velocity_mps] for t in truths])
        self.assertTrue(min(v) < 0 < max(v))

    def test_005_snr_extremes(self):
        frames = 50
        sc = fixed_scene().to_json_string()
        x = random_symbols(frames * N)
        clean, _ = run(channel(sc), x)
        y, tags = run(channel(sc, snr_db=300.0), x)
        np.testing.assert_allclose(y, clean, rtol=1e-6, atol=1e-9)
        self.assertEqual(truth_tags(tags)[0][1][sems.keys.snr_db], 300.0)
        y, _ = run(channel(sc, snr_db=-50.0), x)
        self.assertTrue(np.all(np.isfinite(y)))
        var = np.mean(np.abs(y - clean) ** 2)  # 1600 draws: ±10 % is > 4 standard deviations
        self.assertAlmostEqual(var / 1e5, 1.0, delta=0.1)

    def test_006_set_snr(self):
        ch = channel(fixed_scene().to_json_string(), snr_db=10.0)
        ch.set_snr_db(math.inf)
        self.assertEqual(ch.snr_db(), math.inf)
        x = random_symbols(N)
        y, tags = run(ch, x)
        clean, _ = run(channel(fixed_scene().to_json_string()), x)
        np.testing.assert_array_equal(y, clean)
        self.assertEqual(truth_tags(tags)[0][1][sems.keys.snr_db], math.inf)
        for bad in (math.nan, -math.inf):
            with self.assertRaises(ValueError) as cm:
                ch.set_snr_db(bad)
            self.assertIn("snr_db", str(cm.exception))

    def test_007_amplitude_extremes(self):
        sc = fixed_scene().to_json_string()
        x = random_symbols(2 * N)
        clean, _ = run(channel(sc), x)
        # Noiseless: the SNR is against unit channel power, so noise at any finite SNR
        # would swamp a 1e-20 signal — as it should.
        for amp in (1e-20, 1e20):
            with self.subTest(amplitude=amp):
                y, _ = run(channel(sc), x * np.float32(amp))
                self.assertTrue(np.all(np.isfinite(y)))
                np.testing.assert_allclose(y / amp, clean, rtol=1e-5, atol=1e-6)
        y, _ = run(channel(sc, snr_db=20.0), x * np.float32(1e20))
        self.assertTrue(np.all(np.isfinite(y)))

    def test_008_nonfinite_input_counted(self):
        x = random_symbols(3 * N)
        x[1, 2] = np.nan
        x[5, 0] = np.inf
        x[5, 1] = np.nan
        ch = channel(fixed_scene().to_json_string(), snr_db=20.0)
        y, _ = run(ch, x)
        self.assertEqual(ch.nonfinite_symbols(), 2)
        self.assertEqual(ch.frames(), 3)
        self.assertTrue(np.all(np.isfinite(np.delete(y, [1, 5], axis=0))))

    def test_009_bit_exact_for_any_chunk_size(self):
        # Noise, draws and frame starts do not depend on how work() is called.
        frames = 3
        x = random_symbols(frames * N)
        tags = [frame_tag(f * N, f) for f in range(frames)]
        want, want_tags = run(channel(snr_db=5.0), x, tags)
        for chunk in (1, 3, N + 1):
            with self.subTest(chunk=chunk):
                y, got_tags = run(channel(snr_db=5.0), x, tags, chunk)
                np.testing.assert_array_equal(y, want)
                self.assertEqual(truth_tags(got_tags), truth_tags(want_tags))

    def test_010_bad_input_refused(self):
        def refuses(text, *args, **kw):
            with self.assertRaises(ValueError) as cm:
                channel(*args, **kw)
            self.assertIn(text, str(cm.exception))

        refuses("target_channel scene JSON", '{"format": "sems.scene", "targets": [')
        refuses("target_channel scene JSON", '{"format": "sems.scene", "version": 1, "targets": []}')
        refuses("no_such_scene.json", "/nonexistent/no_such_scene.json")
        refuses("unknown target class \"tank\"", classes=["tank"])
        refuses("random scenes", fixed_scene().to_json_string(), classes=["car"])
        refuses("clutter_paths", clutter_paths=-1)
        refuses("heading", heading="sideways")
        refuses("random scenes", fixed_scene().to_json_string(), heading="any")
        refuses("snr_db", snr_db=math.nan)
        refuses("snr_db", snr_db=-math.inf)
        refuses("n_symbols", n_symbols=0)
        refuses("range", classes=["car"], bandwidth_hz=8 * 3.75e6)  # 40 m unambiguous range
        refuses("track_frames", track_frames=-1)
        refuses("track_frames", track_frames=2**20 + 1)
        refuses("track_gains", track_frames=4, track_gains="swerling")
        refuses("track_frames = 0", track_gains="track")
        refuses("track_coherence_time_s applies to track_gains = \"gauss_markov\"", track_frames=4,
                track_coherence_time_s=0.5)
        refuses("track_coherence_time_s must be", track_frames=4, track_gains="gauss_markov",
                track_coherence_time_s=0.0)
        refuses("track_*", fixed_scene().to_json_string(), track_frames=4)
        refuses("track_motion: unknown track motion \"curved\" (known: radial, straight)", track_frames=4,
                track_motion="curved")
        refuses("track_frames = 0", track_motion="straight")
        refuses("track_*", fixed_scene().to_json_string(), track_motion="straight")

    def test_011_tracks(self):
        # Tracks of 5 frames (drones move < 2 m in 0.16 s, so most run whole): the model's
        # frames and truths, and every truth tag names its track and its place in it.
        frames = 23
        x = random_symbols(frames * N)
        y, tags = run(channel(classes=["drone"], track_frames=5, track_gains="gauss_markov",
                              track_coherence_time_s=0.02), x)
        track = sems.track_draw_spec(frames_min=5, frames_max=5, gains=sems.gain_coherence.gauss_markov,
                                     coherence_time_s=0.02)
        spec = sems.random_spec(classes=[sems.target_class.drone], tracks=track)
        h, truths = sems.channel_model(settings(), sems.scene.random(spec), SEED).generate(frames)
        np.testing.assert_allclose(y, h.reshape(-1, M) * x, rtol=1e-5, atol=1e-6)
        got = [(d[sems.keys.track_id], d[sems.keys.frame_in_track]) for _, d in truth_tags(tags)]
        self.assertEqual(got, [(t[sems.keys.track_id], t[sems.keys.frame_in_track]) for t in truths])
        self.assertEqual(got[:7], [(0, 0), (0, 1), (0, 2), (0, 3), (0, 4), (1, 0), (1, 1)])
        # Bodies moving straight in the ground plane: the block's frames and truths are the model's
        # for the scene it states, and crossing drones' radial velocities change along the track.
        y, tags = run(channel(classes=["drone"], heading="any", track_frames=5, track_motion="straight"), x)
        scene = channel(classes=["drone"], heading="any", track_frames=5, track_motion="straight").scene_json()
        self.assertIn('"motion":"straight"', scene.replace(" ", ""))
        h, truths = sems.channel_model(settings(), sems.scene.parse(scene), SEED).generate(frames)
        np.testing.assert_allclose(y, h.reshape(-1, M) * x, rtol=1e-5, atol=1e-6)
        speeds = [d[sems.keys.velocity_mps] for _, d in truth_tags(tags)]
        self.assertEqual(speeds, [t[sems.keys.velocity_mps] for t in truths])
        self.assertTrue(any(speeds[i] != speeds[i + 1] for i in range(4)))
        # Without tracks every frame is its own track.
        _, tags = run(channel(classes=["drone"]), random_symbols(3 * N))
        self.assertEqual([(d[sems.keys.track_id], d[sems.keys.frame_in_track]) for _, d in truth_tags(tags)],
                         [(0, 0), (1, 0), (2, 0)])

    def test_012_random_scene_array(self):
        # ula4_5g: four receive elements, one transmit element (the preset states none).
        preset, n_rx = "ula4_5g", 4
        frames = 12
        x = random_symbols(frames * N)
        ch = channel(classes=["car"], snr_db=20.0, array=preset, azimuth_min_rad=-0.5, azimuth_max_rad=0.5,
                     n_receive=n_rx)
        self.assertEqual((ch.output_signature().max_streams(), ch.input_signature().max_streams()), (n_rx, 1))
        ys, tags = run_streams(ch, x, n_rx)
        azimuths = []
        for k in range(n_rx):
            truth = truth_tags(tags[k])
            self.assertEqual([o for o, _ in truth], [f * N for f in range(frames)], f"output {k}")
            azimuths.append([d[sems.keys.azimuth_rad] for _, d in truth])
        self.assertEqual(azimuths, [azimuths[0]] * n_rx)  # every output carries the frame's truth
        self.assertTrue(all(-0.5 <= a <= 0.5 for a in azimuths[0]), azimuths[0])
        self.assertGreater(len(set(azimuths[0])), 1, "the azimuths are drawn, not fixed")
        # The parameters mean what a random scene's "array" and "random.azimuth_rad" mean: the
        # same seed gives the same outputs, bit for bit, noise included.
        text = json.dumps({"format": "sems.scene", "version": 1, "array": preset,
                           "random": {"classes": ["car"], "azimuth_rad": [-0.5, 0.5]}})
        want, want_tags = run_streams(channel(text, snr_db=20.0, n_receive=n_rx), x, n_rx)
        for k in range(n_rx):
            np.testing.assert_array_equal(ys[k], want[k], f"output {k}")
            self.assertEqual(truth_tags(tags[k]), truth_tags(want_tags[k]), f"output {k}")
        # No array and no interval (their defaults, or a blank array): one antenna, the frames of a
        # block without them.
        y, _ = run(channel(classes=["car"], snr_db=20.0), x)
        for kw in (dict(array=""), dict(array=" ", azimuth_min_rad=0.0, azimuth_max_rad=0.0)):
            with self.subTest(**kw):
                got, tags = run(channel(classes=["car"], snr_db=20.0, **kw), x)
                np.testing.assert_array_equal(got, y)
                self.assertNotIn(sems.keys.azimuth_rad, truth_tags(tags)[0][1])

    def test_013_array_parameters_refused(self):
        def refuses(text, *args, **kw):
            with self.assertRaises(ValueError) as cm:
                channel(*args, **kw)
            self.assertIn(text, str(cm.exception))

        fixed = fixed_scene().to_json_string()
        # A fixed scene carries its own array and directions.
        for kw in (dict(array="ula4_5g", n_receive=4), dict(azimuth_min_rad=-0.5, azimuth_max_rad=0.5)):
            with self.subTest(**kw):
                refuses("target_channel: classes, n_targets, paths_per_target, micro_doppler, heading, track_*, "
                        "clutter_*, array, azimuth_min_rad and azimuth_max_rad describe random scenes", fixed, **kw)
        # An interval without an array would change nothing.
        refuses("target_channel: azimuth_min_rad = -0.5 and azimuth_max_rad = 0.5 set the targets' directions, "
                "which change nothing without an array", azimuth_min_rad=-0.5, azimuth_max_rad=0.5)
        refuses("azimuth_min_rad = 0 and azimuth_max_rad = 0.5", azimuth_max_rad=0.5)
        # The interval itself, by name.
        with_array = dict(array="ula4_5g", n_receive=4)
        refuses("target_channel: azimuth_min_rad = 0.5 exceeds azimuth_max_rad = -0.5", azimuth_min_rad=0.5,
                azimuth_max_rad=-0.5, **with_array)
        refuses("target_channel: azimuth_max_rad must lie in [-pi, pi] rad, got 4", azimuth_max_rad=4.0, **with_array)
        refuses("target_channel: azimuth_min_rad must lie in [-pi, pi] rad, got -4", azimuth_min_rad=-4.0,
                **with_array)
        refuses("target_channel: azimuth_min_rad must lie in [-pi, pi] rad, got nan", azimuth_min_rad=math.nan,
                **with_array)
        # The array: an unknown preset, JSON that does not parse, streams other than its counts.
        refuses("target_channel: array: array \"no_such_array\": no such file", array="no_such_array")
        refuses("target_channel: array JSON text does not parse", array="{\"receive\": ")
        refuses("target_channel array JSON", array="{\"receive\": {\"ula\": {\"elements\": 4}}}")  # no format
        refuses("target_channel: the scene's array has 4 receive x 1 transmit elements, but n_receive = 1 and "
                "n_transmit = 1", array="ula4_5g")
        refuses("n_receive = 8 and n_transmit = 1", array="ula4_5g", n_receive=8)


if __name__ == "__main__":
    gr_unittest.run(qa_target_channel)
