#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: learning from Python — bundle loading, numpy inference, errors, a tiny train()."""
import json
import os
import tempfile

import numpy as np
from gnuradio import gr_unittest
from gnuradio import sems

SRC = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def fresh_obs(bundle, count, snr_db, seed=99):
    """Pilot observations (count, N_p) from the bundle's frame, at its mask positions."""
    model = sems.channel_model(bundle.frame, sems.scene.random(sems.random_spec()), seed)
    h, truths = model.generate(count)
    h = np.asarray(h).reshape(count, -1)
    rng = np.random.default_rng(seed)
    sigma2 = 10 ** (-snr_db / 10)
    y = h + np.sqrt(sigma2 / 2) * (rng.standard_normal(h.shape) + 1j * rng.standard_normal(h.shape))
    return y[:, bundle.mask.flat_indices()].astype(np.complex64), truths


class qa_learning(gr_unittest.TestCase):
    def test_shipped_classifier_from_numpy(self):
        b = sems.model_bundle.load(os.path.join(SRC, "models", "classifier"))
        self.assertEqual(b.task, sems.task_kind.classify)
        self.assertEqual(b.n_pilots, 32)
        dec = sems.bundle_decoder(b, 1)
        obs, truths = fresh_obs(b, 64, 20.0)
        p = dec.classify(obs)
        self.assertEqual(p.shape, (64, len(b.class_names)))
        np.testing.assert_allclose(p.sum(axis=1), 1.0, atol=1e-5)
        self.assertEqual(dec.features(obs[:5]).shape, (5, dec.feature_size()))
        with self.assertRaises(ValueError):
            dec.classify(np.zeros((3, 31), np.complex64))
        with self.assertRaises(ValueError):
            dec.estimate_delay(obs)

    def test_shipped_delay_from_numpy(self):
        dec = sems.bundle_decoder(os.path.join(SRC, "models", "delay_single"), 1)
        obs = np.zeros((2, 32), np.complex64)
        d = dec.estimate_delay_index(obs)
        self.assertEqual(d.shape, (2,))
        self.assertTrue(np.all(np.isfinite(d)))
        np.testing.assert_allclose(dec.estimate_delay(obs) * 30e6, d, rtol=1e-9)

    def test_non_finite_frame_refused(self):
        # bundle_decoder.h: a batch holding a NaN or Inf frame is refused, naming the frame;
        # no NaN answer comes back.
        cls = sems.bundle_decoder(os.path.join(SRC, "models", "classifier"), 1)
        dly = sems.bundle_decoder(os.path.join(SRC, "models", "delay_single"), 1)
        obs = np.full((5, 32), 0.5 - 0.25j, np.complex64)
        self.assertEqual(cls.classify(obs).shape, (5, 3))
        for bad, pilot in ((complex(np.nan, 0), 7), (complex(0, np.inf), 31), (complex(-np.inf, np.nan), 0)):
            o = obs.copy()
            o[3, pilot] = bad
            for call, name in ((cls.classify, "classify"), (cls.features, "features"),
                               (dly.estimate_delay, "estimate_delay"), (dly.estimate_delay_index, "estimate_delay")):
                with self.assertRaisesRegex(
                        ValueError, r"bundle_decoder::%s: frame 3 of the batch of 5 holds a non-finite "
                                    r"observation \(pilot %d\)" % (name, pilot)):
                    call(o)
        one = np.full(32, np.nan, np.complex64)  # a single frame (N_p,) is frame 0
        with self.assertRaisesRegex(ValueError, "frame 0 of the batch of 1"):
            dly.estimate_delay(one)
        self.assertTrue(np.all(np.isfinite(dly.estimate_delay(obs))))

    def test_missing_bundle(self):
        with self.assertRaisesRegex(ValueError, "does not exist"):
            sems.model_bundle.load("/nonexistent/bundle")

    def test_classifier_chirp_rates(self):
        """The tone fit's rates from the one C++ definition: chirp_bins of them, symmetric, 0 in the
        middle, the largest sweeping chirp_sweep_bins Doppler bins over N symbols (alpha N^2)."""
        n = 32
        r = sems.classifier_chirp_rates('{"chirp_bins": 5, "chirp_sweep_bins": 2.0}', n)
        np.testing.assert_allclose(r, [2.0 * (j - 2) / (2 * n * n) for j in range(5)], rtol=0, atol=1e-15)
        self.assertEqual(sems.classifier_chirp_rates('{"chirp_bins": 1}', n), [0.0])
        self.assertEqual(sems.classifier_chirp_rates('{"chirp_bins": 0}', n), [])
        with self.assertRaisesRegex(ValueError, "chirp_bins"):  # even: not symmetric around 0
            sems.classifier_chirp_rates('{"chirp_bins": 4}', n)
        with self.assertRaisesRegex(ValueError, "chirp_sweep_bins"):
            sems.classifier_chirp_rates('{"chirp_bins": 3, "chirp_sweep_bins": 0}', n)
        with self.assertRaisesRegex(ValueError, "n_symbols"):
            sems.classifier_chirp_rates('{"chirp_bins": 3}', 0)

    def test_tiny_train(self):
        s = sems.training_settings()
        s.task = sems.task_kind.delay
        s.mask_pattern = "random"
        s.frames = 400
        s.epochs = 2
        s.batch = 64
        s.n_pilots = 16
        s.snr_min_db = s.snr_max_db = 30.0
        s.threads = 1
        s.verbose = False
        s.mask_settle_epochs = 0
        s.delay_ce_weight, s.delay_ce_weight_final = 0.5, 0.1
        with tempfile.TemporaryDirectory() as d:
            s.out_dir = d
            r = sems.train(s)
            self.assertEqual(r.test_obs.shape, (40, 16))
            # Every setting set from Python reaches the trainer and its record.
            training = json.loads(r.bundle.training_json)
            self.assertEqual(training["mask_settle_epochs"], 0)
            self.assertEqual((training["delay_ce_weight"], training["delay_ce_weight_final"]), (0.5, 0.1))
            dec = sems.bundle_decoder(d, 1)
            np.testing.assert_allclose(dec.estimate_delay_index(r.test_obs), r.test_delay_index, atol=1e-4)
        for name, bad in (("mask_settle_epochs", -1), ("delay_ce_weight", -0.5), ("delay_ce_weight_final", float("nan")),
                          ("training_data", "disk")):
            t = sems.training_settings()
            setattr(t, name, bad)
            with self.assertRaisesRegex(ValueError, name):
                t.validate()

    def test_tiny_track_training(self):
        # A decision over a track on the shipped classifier, from Python: train_track writes a
        # track bundle; track_classifier gives its evidence and steps through a track, the
        # fusion beside it being the softmax of the summed frame log-probabilities.
        with tempfile.TemporaryDirectory() as d:
            s = sems.track_training_settings()
            s.frame_bundle = os.path.join(SRC, "models", "classifier")
            s.track_frames = 3
            s.tracks = 40
            s.epochs = 1
            s.threads = 1
            s.eval_snr_db = [10.0]
            s.eval_frames = [1, 3]
            s.temporal_json = json.dumps({"hidden": 8})
            s.out_dir = os.path.join(d, "track")
            s.verbose = False
            r = sems.train_track(s)
            metrics = json.loads(r.metrics_json)
            self.assertEqual([row["frames"] for row in metrics["by_snr"][0]["by_frames"]], [1, 3])
            b = sems.model_bundle.load(s.out_dir)
            self.assertTrue(sems.track_classifier.is_track_bundle(b))
            self.assertEqual(json.loads(b.track_json)["frames"], 3)
            tc = sems.track_classifier(s.out_dir)
            obs, _ = fresh_obs(b, 4, 10.0)
            ev = tc.evidence(obs)
            self.assertEqual(ev.shape, (4, tc.evidence_size()))
            st = tc.begin()
            for f in range(4):
                p, q = tc.step(st, ev[f])
                self.assertAlmostEqual(float(p.sum()), 1.0, places=5)
                fused = ev[:f + 1, -tc.n_classes():].sum(axis=0)
                want = np.exp(fused - fused.max()) / np.exp(fused - fused.max()).sum()
                np.testing.assert_allclose(q, want, rtol=1e-4, atol=1e-6)
            self.assertEqual(st.frames, 4)
            with self.assertRaises(ValueError):
                tc.step(st, ev[0][:-1])
            with self.assertRaises(ValueError):
                sems.track_classifier(os.path.join(SRC, "models", "classifier"))
            s.track_frames = 0
            with self.assertRaises(ValueError):
                s.validate()

    def test_super_frame_bundle_sets(self):
        # The shipped classifier's files with a mask of two sets (its own, then the staggered
        # pattern): frames of set 1 get the answers of the same weights on the staggered pattern
        # alone; a batch without sets is refused naming F, and sets of another length too.
        with tempfile.TemporaryDirectory() as d:
            src = os.path.join(SRC, "models", "classifier")
            b = sems.model_bundle.load(src)
            with open(os.path.join(src, "mask.json")) as f:
                own = json.load(f)
            other = sems.pilot_mask.from_pattern("staggered", b.frame.n_symbols, b.frame.n_subcarriers, b.n_pilots)
            pilots = [[int(i) // b.frame.n_subcarriers, int(i) % b.frame.n_subcarriers] for i in other.flat_indices()]
            two = {k: v for k, v in own.items() if k not in ("pilots", "n_pilots", "power", "phases")}
            two["frames"] = [{"pilots": own["pilots"]}, {"pilots": pilots}]
            alone = dict(own, pilots=pilots, n_pilots=len(pilots))
            for name, mask in (("two", two), ("alone", alone)):
                os.makedirs(os.path.join(d, name))
                for f in ("bundle.json", "decoder.pt"):
                    with open(os.path.join(src, f), "rb") as i, open(os.path.join(d, name, f), "wb") as o:
                        o.write(i.read())
                with open(os.path.join(d, name, "mask.json"), "w") as o:
                    json.dump(mask, o)
            bt = sems.model_bundle.load(os.path.join(d, "two"))
            self.assertEqual(bt.super_frames, 2)
            self.assertEqual(list(bt.mask_of_set(1).flat_indices()), list(other.flat_indices()))
            dec = sems.bundle_decoder(bt, 1)
            self.assertEqual(dec.super_frames(), 2)
            rng = np.random.default_rng(3)
            obs = (rng.standard_normal((4, b.n_pilots)) + 1j * rng.standard_normal((4, b.n_pilots))).astype(np.complex64)
            sets = np.array([0, 1, 1, 0], np.int32)
            got = dec.classify(obs, sets)
            want0 = sems.bundle_decoder(b, 1).classify(obs)
            want1 = sems.bundle_decoder(os.path.join(d, "alone"), 1).classify(obs)
            np.testing.assert_allclose(got[[0, 3]], want0[[0, 3]], atol=1e-5)
            np.testing.assert_allclose(got[[1, 2]], want1[[1, 2]], atol=1e-5)
            self.assertGreater(np.abs(want0 - want1).max(), 1e-3)
            with self.assertRaisesRegex(ValueError, "super-frame of 2 frames"):
                dec.classify(obs)
            with self.assertRaises(ValueError):
                dec.classify(obs, np.array([0, 1], np.int32))


if __name__ == "__main__":
    gr_unittest.run(qa_learning)
