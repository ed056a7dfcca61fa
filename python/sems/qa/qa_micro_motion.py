#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Micro-motion targets and class libraries from Python: scenes with each scatterer model
(rotor, walker, wheels, point scatterers) generate frames; class libraries round-trip
through JSON; the target channel blocks draw from a library and tag the target's model,
its drawn parameters and the library; a classifier refuses frames of another library."""
import json
import math
import os

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
SEED = 7


def kinematic():
    return sems.class_library.find("kinematic")


def one_target_scene(lib, cls_name, motion, speed=5.0, heading=0.3):
    """A fixed scene of one target of class `cls_name` of `lib`, or (scene.fixed checks the
    ids against the paper's table before with_library) of class 0 when its id is beyond it."""
    cls = lib.id_of(cls_name)
    t = sems.target_spec(cls if cls < 3 else 0, 60.0, speed * math.cos(heading), motion=motion,
                         speed_mps=speed, heading_rad=heading)
    return sems.scene.fixed([t], fading=sems.fading_kind.none).with_library(lib)


def run_channel(block, items, vlen):
    """Streams `items` items of vlen ones through a channel block; returns its truth tags."""
    src = blocks.vector_source_c(np.ones(items * vlen, np.complex64).tolist(), False, vlen)
    snk = blocks.vector_sink_c(vlen)
    tb = gr.top_block()
    tb.connect(src, block, snk)
    tb.run()
    return [(t.offset, pmt.to_python(t.value)) for t in snk.tags()
            if pmt.symbol_to_string(t.key) == sems.keys.truth_tag]


class qa_micro_motion(gr_unittest.TestCase):
    def test_001_each_model_generates_frames(self):
        lib = kinematic()
        fs = sems.frame_settings()
        models = {
            "rotor": ("quadcopter", sems.rotor_motion(rotors=4, blades=2, blade_length_m=0.1, rotation_hz=[90.0])),
            "walker": ("adult", sems.walker_motion(height_m=1.8, phase_rad=0.5)),
            "wheels": ("car", sems.wheels_motion(wheels=4, wheel_radius_m=0.3, rim_points=8, spokes=5)),
            "scatterers": ("bicyclist", sems.scatterers_motion([
                sems.point_scatterer(1.0),
                sems.point_scatterer(0.5, [sems.harmonic(0.05, 1.4, 0.0), sems.harmonic(0.01, 2.8, 1.0)])])),
        }
        for model, (cls_name, motion) in models.items():
            self.assertEqual(sems.micro_motion_model(motion), model)
            j = json.loads(sems.micro_motion_to_json(motion))
            self.assertEqual(j["model"], model)
            sc = one_target_scene(lib, cls_name, motion, speed=1.5 if model == "walker" else 5.0)
            self.assertEqual(sc.library().name(), "kinematic")
            cls = int(sc.targets()[0].cls)
            self.assertEqual(sc.class_name(cls), lib.class_names()[cls])
            self.assertEqual(sems.micro_motion_model(sc.targets()[0].motion), model)
            cm = sems.channel_model(fs, sc, SEED)
            r = cm.draw(0)
            self.assertEqual(len(r.bodies), 1, model)
            self.assertEqual(r.truth_body, 0, model)
            self.assertEqual([p.body for p in r.paths], [0])
            self.assertEqual(sems.micro_motion_model(r.bodies[0].motion), model)
            self.assertEqual(r.bodies[0].speed_mps, 1.5 if model == "walker" else 5.0)
            self.assertEqual(r.truth[sems.keys.micro_motion], model)
            self.assertEqual(r.truth[sems.keys.class_name], lib.class_names()[cls])
            h, truths = cm.generate(2)
            self.assertEqual(h.shape, (2, fs.n_symbols, fs.n_subcarriers))
            self.assertTrue(np.all(np.isfinite(h)), model)
            # Unit mean power without fading, to the models' normalisation (a few frames of a
            # slow gait or rotation are not a whole period: a loose bound).
            self.assertGreater(float(np.mean(np.abs(h) ** 2)), 0.2, model)
            self.assertLess(float(np.mean(np.abs(h) ** 2)), 5.0, model)
            # The scatterers move: H differs from the same target as a point.
            point = sc.targets()[0]
            point.motion = None
            h_point, _ = sems.channel_model(fs, sems.scene.fixed([point], fading=sems.fading_kind.none)
                                            .with_library(lib), SEED).generate(2)
            self.assertGreater(float(np.linalg.norm(h - h_point) / np.linalg.norm(h_point)), 0.1, model)
            self.assertEqual([t[sems.keys.micro_motion] for t in truths], [model, model])

    def test_002_point_target_has_no_body(self):
        sc = sems.scene.fixed([sems.target_spec(sems.target_class.car, 50.0, 10.0)])
        r = sems.channel_model(sems.frame_settings(), sc, SEED).draw(0)
        self.assertEqual(r.truth_body, -1)
        self.assertEqual(len(r.bodies), 0)
        self.assertEqual(r.paths[0].body, -1)
        self.assertEqual(r.truth[sems.keys.micro_motion], "none")
        # truth_body: the target of interest's body among the frame's bodies.
        rotor, walker = sems.rotor_motion(rotation_hz=[50.0]), sems.walker_motion()
        point = sems.target_spec(sems.target_class.car, 50.0, 10.0)
        flyer = sems.target_spec(sems.target_class.drone, 80.0, 5.0, motion=rotor)
        person = sems.target_spec(sems.target_class.pedestrian, 30.0, 1.2, motion=walker)
        for targets, toi, want in (([point, flyer], 1, 0), ([flyer, person], 1, 1), ([flyer, point], 1, -1),
                                   ([point, person, flyer], 2, 1)):
            r = sems.channel_model(sems.frame_settings(), sems.scene.fixed(targets, target_of_interest=toi), SEED).draw(0)
            self.assertEqual(r.truth_body, want, (toi, want))
            if want >= 0:
                self.assertEqual(r.bodies[want].motion, targets[toi].motion)

    def test_003_class_library_round_trip(self):
        paper = sems.class_library.paper()
        self.assertEqual(paper.name(), "paper")
        self.assertEqual(paper.class_names(), ["pedestrian", "car", "drone"])
        self.assertEqual(sems.class_library.find("paper").class_names(), paper.class_names())
        lib = kinematic()
        self.assertEqual(lib.size(), len(lib.class_names()))
        self.assertEqual(lib.class_names()[lib.id_of("car")], "car")
        self.assertEqual(lib.at(lib.id_of("quadcopter")).motion_model(), "rotor")
        again = sems.class_library.from_json(lib.to_json(), "round trip")
        self.assertEqual(again.class_names(), lib.class_names())
        self.assertTrue(again.same_classes(lib))
        self.assertEqual(again.difference(lib), "")
        self.assertIn("classes", paper.difference(lib))
        from_file = sems.class_library.load(os.path.join(SOURCE, "models", "classes", "kinematic.json"))
        self.assertTrue(from_file.same_classes(lib))
        with self.assertRaises(ValueError):
            lib.id_of("tractor")
        with self.assertRaises(ValueError):
            sems.class_library.find("no_such_library")
        with self.assertRaises(ValueError):
            sems.class_library.from_json("{not json", "bad text")

    def test_004_random_scene_of_a_library_and_track(self):
        lib = kinematic()
        sc = sems.scene.random(sems.random_spec(classes=[]), library=lib)
        self.assertEqual(sc.library().name(), "kinematic")
        self.assertEqual(len(sc.label_classes()), lib.size())
        cm = sems.channel_model(sems.frame_settings(), sc, SEED)
        _, truths = cm.generate(12)
        for t in truths:
            self.assertIn(t[sems.keys.class_name], lib.class_names())
            self.assertEqual(t[sems.keys.micro_motion], lib.at(t[sems.keys.class_id]).motion_model())
        moving = sems.scene.fixed([sems.target_spec(sems.target_class.car, 50.0, 10.0)]).with_track(
            sems.track_spec(40.0, 60.0, sems.track_bound.reflect))
        self.assertEqual(moving.track().at_bound, sems.track_bound.reflect)
        _, truths = sems.channel_model(sems.frame_settings(), moving, SEED).generate(3)
        self.assertLess(truths[1][sems.keys.range_m], truths[0][sems.keys.range_m])  # approaching

    def test_005_target_channel_tags_micro_motion(self):
        fs = sems.frame_settings()
        for make, items, vlen in ((sems.target_channel, 3 * fs.n_symbols, fs.n_subcarriers),
                                  (sems.target_channel_td, 3 * fs.n_symbols * (fs.n_subcarriers + fs.cp_len), 1)):
            block = make(class_library="kinematic", classes=["quadcopter", "adult"], seed=SEED)
            tags = run_channel(block, items, vlen)
            self.assertEqual(len(tags), 3)
            model = sems.channel_model(fs, sems.scene.random(
                sems.random_spec(classes=[kinematic().id_of("quadcopter"), kinematic().id_of("adult")]),
                library=kinematic()), SEED)
            for f, (_, d) in enumerate(tags):
                self.assertEqual(d[sems.keys.class_library], "kinematic")
                r = model.draw(f)
                self.assertEqual(d[sems.keys.class_name], r.truth[sems.keys.class_name])
                self.assertEqual(d[sems.keys.micro_motion], r.truth[sems.keys.micro_motion])
                params = d[sems.keys.micro_motion_params]
                body = r.bodies[r.truth_body]
                want = json.loads(sems.micro_motion_to_json(body.motion))
                self.assertEqual({k: params[k] for k in want}, want)
                self.assertEqual(params["speed_mps"], body.speed_mps)
            self.assertEqual(json.loads(block.scene_json())["classes"], "kinematic")

    def test_006_paper_tags_and_refusals(self):
        block = sems.target_channel(classes=["car"], seed=SEED)
        (_, d), = run_channel(block, sems.frame_settings().n_symbols, 64)
        self.assertEqual(d[sems.keys.class_library], "paper")
        self.assertEqual(d[sems.keys.micro_motion], "none")  # the paper's car has no micro-Doppler
        self.assertIsNone(d[sems.keys.micro_motion_params])
        scene_json = sems.scene.fixed([sems.target_spec(sems.target_class.car, 50.0, 10.0)]).to_json_string()
        for make in (sems.target_channel, sems.target_channel_td):
            with self.assertRaisesRegex(ValueError, "class_library"):
                make(scene=scene_json, class_library="kinematic")
            with self.assertRaisesRegex(ValueError, "class_library"):
                make(class_library="no_such_library")
            with self.assertRaisesRegex(ValueError, "kinematic"):
                make(class_library="kinematic", classes=["drone"])

    def test_007_classifier_refuses_another_library(self):
        bundle_dir = os.path.join(SOURCE, "models", "classifier")
        bundle = sems.model_bundle.load(bundle_dir)
        self.assertEqual(bundle.library.name(), "paper")  # absent from the shipped bundle.json: the paper's
        bundle.check_library(sems.class_library.paper(), "test")
        with self.assertRaisesRegex(RuntimeError, "paper.*kinematic"):
            bundle.check_library(kinematic(), "test")
        n_p = bundle.n_pilots
        obs = (np.random.default_rng(1).standard_normal((4, n_p)) * (1 + 1j)).astype(np.complex64)
        for library, want_frames in (("paper", 4), ("kinematic", 0)):
            truth = pmt.make_dict()
            truth = pmt.dict_add(truth, pmt.intern(sems.keys.class_name), pmt.intern("car"))
            truth = pmt.dict_add(truth, pmt.intern(sems.keys.class_library), pmt.intern(library))
            tags = [gr.tag_utils.python_to_tag((0, pmt.intern(sems.keys.truth_tag), truth, pmt.intern("test")))]
            sink = sems.classifier_sink(bundle_dir, n_p, batch_size=1)
            tb = gr.top_block()
            tb.connect(blocks.vector_source_c(obs.reshape(-1).tolist(), False, n_p, tags), sink)
            tb.run()  # a refused stream ends (it does not hang the flowgraph)
            self.assertEqual(sink.frames(), want_frames, library)

    def test_008_link_budget_sets_the_truth_snr(self):
        """A scene with a link budget through the channel block: the truth's snr_db is the radar
        equation's SNR at the target's range and RCS plus the block's SNR setting."""
        text = json.dumps({"format": "sems.scene", "version": 1, "fading": "none",
                           "link_budget": {"tx_power_dbm": 10, "tx_gain_dbi": 10, "rx_gain_dbi": 10,
                                           "noise_figure_db": 8, "system_loss_db": 3},
                           "targets": [{"class": "car", "range_m": 40, "velocity_mps": 3, "rcs_dbsm": 10}]})
        sc = sems.scene.parse(text)
        fs = sems.frame_settings()
        want = sc.budget().snr_db(fs, 40.0, 10.0)
        lam, k_t0 = 3e8 / fs.carrier_hz, 1.380649e-23 * 290.0
        closed = 10 * math.log10(1e-2 * 10 * 10 * lam ** 2 * 10 / ((4 * math.pi) ** 3 * 40.0 ** 4 * k_t0 *
                                                                    10 ** 0.8 * fs.bandwidth_hz * 10 ** 0.3))
        self.assertAlmostEqual(want, closed, places=9)
        block = sems.target_channel(scene=text, snr_db=5.0, seed=SEED)
        (_, d), = run_channel(block, fs.n_symbols, fs.n_subcarriers)
        self.assertAlmostEqual(d[sems.keys.snr_db], want + 5.0, places=9)
        # The same from Python objects: a target with an RCS and a budget set on the scene.
        b = sems.link_budget()
        b.tx_power_dbm, b.tx_gain_dbi, b.rx_gain_dbi, b.noise_figure_db, b.system_loss_db = 10, 10, 10, 8, 3
        t = sems.target_spec(sems.class_from_name("car"), 40.0, 3.0, rcs_dbsm=10.0)
        sc2 = sems.scene.fixed([t]).with_budget(b)
        r = sems.channel_model(fs, sc2, SEED).draw(0)
        self.assertAlmostEqual(r.truth[sems.keys.link_snr_db], want, places=9)
        with self.assertRaisesRegex(ValueError, "rcs_dbsm"):
            sems.scene.fixed([sems.target_spec(sems.class_from_name("car"), 40.0, 3.0)]).with_budget(b)


if __name__ == "__main__":
    gr_unittest.run(qa_micro_motion)
