#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""One fact in one place: every GRC default that has a C++ counterpart equals the C++ default.

Loads every grc/sems_*.block.yml and compares each default with the value the C++ code
holds, read through the bindings from the objects themselves (a block built with its
defaults and asked through its getters; frame_settings(); sink_defaults; the random scene
a default target_channel draws from). A default the table below does not know fails the
test, so a new GRC parameter has to be classified here: compared with C++, or explicitly
GRC-only (with the reason). Every parameter must also be documented in the block's
`documentation:` field (a "- <label>: ..." line).
"""
import glob
import inspect
import json
import math
import os
import unittest

import yaml

from gnuradio import gr_unittest
from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
GRC_DIR = os.path.join(SOURCE, "grc")
BUNDLES = os.path.join(SOURCE, "models")


def grc_value(text):
    """A GRC default as GRC evaluates it (a Python expression)."""
    return eval(str(text), {"__builtins__": {"float": float, "True": True, "False": False}})


def cxx_defaults():
    """block id -> {parameter id -> the C++ default}."""
    fs = sems.frame_settings()
    frame = {
        "n_symbols": fs.n_symbols,
        "n_subcarriers": fs.n_subcarriers,
        "bandwidth_hz": fs.bandwidth_hz,
        "carrier_hz": fs.carrier_hz,
        "symbol_interval_s": fs.symbol_interval_s,
    }
    # target_channel with every default: its getters and the random scene it draws from.
    ch = sems.target_channel()
    rnd = json.loads(ch.scene_json())
    spec = rnd["random"]
    channel = dict(frame)
    channel.update({
        "snr_db": ch.snr_db(),
        "n_targets": spec["targets"],
        "paths_per_target": spec["paths_per_target"],
        "micro_doppler": spec["micro_doppler"],
        "heading": spec["heading"],
        "clutter_paths": (rnd.get("clutter") or {}).get("paths", 0),
        "classes": [] if sorted(spec["classes"]) == sorted(sems.class_names()) else spec["classes"],
        # seed: no getter; the bindings' default is make()'s (checked through the signature).
        "seed": bound_default(sems.target_channel, "seed"),
        "clutter_csr_db": bound_default(sems.target_channel, "clutter_csr_db"),
        "class_library": bound_default(sems.target_channel, "class_library"),
        # tracks: off by default (the scene has none); their settings' defaults are the
        # core's track_draw_spec, which the bindings take.
        "track_frames": spec.get("tracks", {}).get("frames", 0),
        "track_gains": sems.gain_coherence_name(sems.track_draw_spec().gains),
        "track_coherence_time_s": sems.track_draw_spec().coherence_time_s,
        "track_motion": sems.track_motion_name(sems.track_draw_spec().motion),
        # streams: one of each without an array (what the default block has).
        "n_receive": ch.output_signature().max_streams(),
        "n_transmit": ch.input_signature().max_streams(),
        # array: no getter; the bindings' default is make()'s (none). The azimuth interval: the
        # default block's random scene, which states none (0, 0: boresight).
        "array": bound_default(sems.target_channel, "array"),
        "azimuth_min_rad": spec.get("azimuth_rad", [0.0, 0.0])[0],
        "azimuth_max_rad": spec.get("azimuth_rad", [0.0, 0.0])[1],
    })
    # pilot_mapper / pilot_extractor: built with one pilot, every other argument defaulted.
    mapper = sems.pilot_mapper(pilot_positions=[0])
    extractor = sems.pilot_extractor(pilot_positions=[0])
    pilot_frame = {"n_symbols": fs.n_symbols, "n_subcarriers": fs.n_subcarriers}
    mapper_d = dict(pilot_frame, pilot_symbol=mapper.mask().pilot_symbol(),
                    pilot_power=mapper.pilot_power(), data_power=mapper.data_power(),
                    guard_subcarriers=bound_default(sems.pilot_mapper, "guard_subcarriers"))
    assert (mapper.mask().n_symbols(), mapper.mask().n_subcarriers()) == (fs.n_symbols, fs.n_subcarriers)
    extractor_d = dict(pilot_frame, pilot_symbol=extractor.mask().pilot_symbol(), n_elements=extractor.n_elements())
    sink = dict(pilot_frame, batch_size=sems.sink_defaults.batch_size, threads=sems.sink_defaults.threads,
                metrics_period=sems.sink_defaults.metrics_period,
                frame=bound_default(sems.classifier_sink, "frame"))
    assert bound_default(sems.delay_estimator_sink, "frame") == sink["frame"]
    ofdm = {"n_subcarriers": fs.n_subcarriers, "cp_len": fs.cp_len}
    # target_channel_td: the same scene options as target_channel, plus its frame's cp_len.
    td = sems.target_channel_td()
    td_rnd = json.loads(td.scene_json())
    td_frame = td.settings()
    channel_td = dict(channel)
    channel_td.update({
        "n_symbols": td_frame.n_symbols, "n_subcarriers": td_frame.n_subcarriers,
        "bandwidth_hz": td_frame.bandwidth_hz, "carrier_hz": td_frame.carrier_hz,
        "symbol_interval_s": td_frame.symbol_interval_s, "snr_db": td.snr_db(), "cp_len": td_frame.cp_len,
        "n_targets": td_rnd["random"]["targets"], "paths_per_target": td_rnd["random"]["paths_per_target"],
        "micro_doppler": td_rnd["random"]["micro_doppler"],
        "seed": bound_default(sems.target_channel_td, "seed"),
        "clutter_csr_db": bound_default(sems.target_channel_td, "clutter_csr_db"),
        "n_receive": td.output_signature().max_streams(),
        "n_transmit": td.input_signature().max_streams(),
        "array": bound_default(sems.target_channel_td, "array"),
        "azimuth_min_rad": td_rnd["random"].get("azimuth_rad", [0.0, 0.0])[0],
        "azimuth_max_rad": td_rnd["random"].get("azimuth_rad", [0.0, 0.0])[1],
    })
    # frame_sync: no getters for its settings; the bindings' defaults (make()'s).
    sync = {name: bound_default(sems.frame_sync, name)
            for name in ("pilot_symbol", "pilot_power", "search_frames", "threshold", "cp_len", "noncoherent")}
    sync.update(pilot_frame)
    # range_doppler_map: no getters for its settings; the bindings' defaults (make()'s).
    rd_map = {name: bound_default(sems.range_doppler_map, name)
              for name in ("window", "n_symbols", "n_subcarriers")}
    ra_map = {name: bound_default(sems.range_angle_map, name)
              for name in ("window", "n_symbols", "n_subcarriers", "n_angles")}
    # tag_file_sink / tag_file_replay: Python blocks, their constructors' defaults.
    from gnuradio.sems.tag_file import tag_file_replay, tag_file_sink
    tag_files = {cls.__name__: {name: p.default for name, p in inspect.signature(cls.__init__).parameters.items()
                                if name not in ("self", "path")}
                 for cls in (tag_file_sink, tag_file_replay)}
    pn_source = {name: bound_default(sems.phase_noise_source, name)
                 for name in ("sample_rate_hz", "dbc_hz", "offset_hz", "seed")}
    # radio_front_end: a Python hier block, its constructor's defaults.
    fe_params = inspect.signature(sems.radio_front_end.__init__).parameters
    front_end = {name: fe_params[name].default
                 for name in ("radio", "tx_power", "class_library", "classes", "n_targets", "snr_db", "seed",
                              "n_symbols", "n_subcarriers", "bandwidth_hz", "carrier_hz", "symbol_interval_s",
                              "cp_len", "n_receive")}
    front_end["classes"] = list(front_end["classes"])
    # The Frame parameter: compared as the frame it names (test_defaults_agree); the C++ default
    # of the blocks with numbers is frame_settings(), the sinks' is their `frame` argument's.
    # The prefix of the time-domain blocks is the frame's there (GRC_ONLY, test_one_cp_default).
    for d in (front_end, channel, mapper_d, extractor_d, ofdm, channel_td, sync, rd_map, ra_map):
        d["frame"] = fs
        d.pop("cp_len", None)
    return {
        "sems_phase_noise_source": pn_source,
        "sems_radio_front_end": front_end,
        "sems_target_channel": channel,
        "sems_pilot_mapper": mapper_d,
        # mimo_pilot_mapper: its powers' getters; its outputs come from the MIMO mask file.
        "sems_mimo_pilot_mapper": {"pilot_power": bound_default(sems.mimo_pilot_mapper, "pilot_power"),
                                   "data_power": bound_default(sems.mimo_pilot_mapper, "data_power"), "frame": fs},
        "sems_pilot_extractor": extractor_d,
        "sems_classifier_sink": dict(sink, **{name: bound_default(sems.classifier_sink, name)
                                              for name in ("track_idle_s", "super_frames", "n_elements", "array")}),
        "sems_delay_estimator_sink": sink,
        "sems_position_sink": {name: sink[name] for name in ("batch_size", "threads", "metrics_period")} |
        {"frame": bound_default(sems.position_sink, "frame")},
        "sems_ofdm_tx": ofdm,
        "sems_ofdm_rx": ofdm,
        "sems_metrics_printer": {},
        "sems_target_channel_td": channel_td,
        "sems_frame_sync": sync,
        "sems_cfo_corrector": dict({name: bound_default(sems.cfo_corrector, name)
                                    for name in ("symbols", "forgetting", "snr_db")}, frame=fs),
        "sems_leakage_canceller": {name: bound_default(sems.leakage_canceller, name)
                                   for name in ("taps", "window", "forgetting", "widely_linear", "dc", "clip_level")},
        "sems_range_doppler_map": rd_map,
        "sems_range_angle_map": ra_map,
        "sems_tag_file_sink": tag_files["tag_file_sink"],
        "sems_tag_file_replay": tag_files["tag_file_replay"],
    }


def bound_default(cls, name):
    """The default pybind11 shows for `name` in the constructor's signature."""
    first = cls.__init__.__doc__.splitlines()[0]
    for part in first[first.index("(") + 1:first.rindex(")")].split(", "):
        if part.startswith(name + ":") and " = " in part:
            return grc_value(part.split(" = ", 1)[1])
    raise AssertionError(f"{cls.__name__}: no default for {name} in {first}")


# The blocks that take the frame (one Frame parameter), and those of them at sample level (which
# also take an optional cyclic prefix). tag_file_sink and phase_noise_source keep their own
# sample rate: they record or drive any stream, not only a frame's samples.
TIME_DOMAIN = ("sems_ofdm_tx", "sems_ofdm_rx", "sems_target_channel_td", "sems_frame_sync",
               "sems_radio_front_end", "sems_cfo_corrector")
FRAME_BLOCKS = TIME_DOMAIN + ("sems_pilot_mapper", "sems_mimo_pilot_mapper", "sems_pilot_extractor", "sems_target_channel",
                              "sems_range_doppler_map", "sems_range_angle_map", "sems_classifier_sink",
                              "sems_delay_estimator_sink", "sems_position_sink")

# GRC-only parameters (no C++ default to agree with), and why.
GRC_ONLY = {
    **{(block, "cp_len"): "-1: the Frame's prefix; C++ and Python take the prefix itself" for block in TIME_DOMAIN},
    ("sems_target_channel", "scene_kind"): "GRC chooser between random / file / JSON scene",
    ("sems_target_channel", "scene_file"): "the chosen scene's path (C++ scene = '' means random)",
    ("sems_target_channel", "scene_json"): "the chosen scene's JSON text",
    ("sems_pilot_mapper", "mask_source"): "GRC chooser between a mask file and positions",
    ("sems_pilot_mapper", "mask_file"): "required in C++ (one of mask_file / positions)",
    ("sems_pilot_mapper", "pilot_positions"): "required in C++ (one of mask_file / positions)",
    ("sems_mimo_pilot_mapper", "mimo_mask_file"): "required in C++",
    ("sems_mimo_pilot_mapper", "n_transmit"): "required in C++ (must be the file's)",
    ("sems_pilot_extractor", "mask_source"): "GRC chooser between a mask file and positions",
    ("sems_pilot_extractor", "mask_file"): "required in C++ (one of mask_file / positions)",
    ("sems_pilot_extractor", "pilot_positions"): "required in C++ (one of mask_file / positions)",
    ("sems_pilot_extractor", "n_pilots"): "GRC-side vector length; C++ takes it from the mask",
    ("sems_classifier_sink", "bundle_dir"): "required in C++",
    ("sems_classifier_sink", "n_pilots"): "required in C++",
    ("sems_delay_estimator_sink", "bundle_dir"): "required in C++",
    ("sems_delay_estimator_sink", "n_pilots"): "required in C++",
    ("sems_position_sink", "bundle_dir"): "required in C++",
    ("sems_position_sink", "n_elements"): "required in C++",
    ("sems_position_sink", "n_pilots"): "required in C++",
    ("sems_metrics_printer", "label"): "Python-only block",
    ("sems_target_channel_td", "scene_kind"): "GRC chooser between random / file / JSON scene",
    ("sems_target_channel_td", "scene_file"): "the chosen scene's path",
    ("sems_target_channel_td", "scene_json"): "the chosen scene's JSON text",
    ("sems_frame_sync", "mask_source"): "GRC chooser between a mask file and positions",
    ("sems_frame_sync", "mask_file"): "required in C++ (one of mask_file / positions)",
    ("sems_frame_sync", "pilot_positions"): "required in C++ (one of mask_file / positions)",
    ("sems_range_doppler_map", "mask_source"): "GRC chooser between a mask file and positions",
    ("sems_range_doppler_map", "mask_file"): "required in C++ (one of mask_file / positions)",
    ("sems_range_doppler_map", "pilot_positions"): "required in C++ (one of mask_file / positions)",
    ("sems_range_doppler_map", "n_pilots"): "GRC-side vector length; C++ takes it from the mask",
    ("sems_range_angle_map", "array"): "required in C++",
    ("sems_range_angle_map", "n_elements"): "GRC-side vector length; C++ takes it from the array",
    ("sems_range_angle_map", "mask_source"): "GRC chooser between a mask file and positions",
    ("sems_range_angle_map", "mask_file"): "required in C++ (one of mask_file / positions)",
    ("sems_range_angle_map", "pilot_positions"): "required in C++ (one of mask_file / positions)",
    ("sems_range_angle_map", "n_pilots"): "GRC-side vector length; C++ takes it from the mask",
    ("sems_tag_file_sink", "path"): "required in Python",
    ("sems_tag_file_replay", "path"): "required in Python",
    ("sems_radio_front_end", "settings"): "GRC-side dict of front_end_settings fields (Python **settings)",
    ("sems_radio_front_end", "scene_kind"): "GRC chooser between random / file scene",
    ("sems_radio_front_end", "scene_file"): "the chosen scene's path",
}

def load_blocks():
    files = sorted(glob.glob(os.path.join(GRC_DIR, "sems_*.block.yml")))
    assert files, f"no GRC blocks under {GRC_DIR}"
    return {os.path.basename(f)[:-len(".block.yml")]: yaml.safe_load(open(f)) for f in files}


def same(a, b):
    if isinstance(a, complex) or isinstance(b, complex):
        return complex(a) == complex(b)
    if isinstance(a, float) or isinstance(b, float):
        return (math.isinf(a) and math.isinf(b) and (a > 0) == (b > 0)) or float(a) == float(b)
    if isinstance(a, str) and a in ("True", "False"):
        a = a == "True"
    return a == b


class qa_grc_defaults(gr_unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.blocks = load_blocks()
        cls.cxx = cxx_defaults()

    def test_every_block_known(self):
        self.assertEqual(sorted(self.blocks), sorted(self.cxx))

    def test_defaults_agree(self):
        checked = 0
        for block, d in self.blocks.items():
            for p in d.get("parameters", []):
                key = (block, p["id"])
                if key in GRC_ONLY:
                    self.assertNotIn(p["id"], self.cxx[block], f"{key} is both GRC-only and compared")
                    continue
                self.assertIn(p["id"], self.cxx[block],
                              f"{block}.{p['id']}: default {p.get('default')!r} is neither compared with a "
                              f"C++ default nor listed as GRC-only")
                # An enum's default is an option name, a string's (or a path's) its text, not an expression.
                grc = str(p["default"]) if p.get("dtype") in ("enum", "string", "file_open") else grc_value(p["default"])
                cxx = self.cxx[block][p["id"]]
                if p["id"] == "frame":  # a frame's name: the frames it names must be equal
                    grc, cxx = sems.frame_of(grc), sems.frame_of(cxx)
                self.assertTrue(same(grc, cxx), f"{block}.{p['id']}: GRC default {grc!r} != C++ default {cxx!r}")
                checked += 1
        self.assertGreaterEqual(checked, 30)

    def test_python_hier_defaults(self):
        # ofdm_tx / ofdm_rx are Python hier blocks: their defaults come from frame_settings too.
        fs = sems.frame_settings()
        for cls in (sems.ofdm_tx, sems.ofdm_rx):
            sig = inspect.signature(cls.__init__).parameters
            self.assertEqual(sig["n_subcarriers"].default, fs.n_subcarriers, cls.__name__)
            self.assertEqual(sig["cp_len"].default, fs.cp_len, cls.__name__)

    def test_one_cp_default(self):
        # Every time-domain block takes its cyclic prefix from its Frame unless told otherwise
        # (-1), and the default frame's is frame_settings' one, which C++ and Python use too.
        cp = sems.frame_settings().cp_len
        for block in TIME_DOMAIN:
            p = [p for p in self.blocks[block]["parameters"] if p["id"] == "cp_len"][0]
            self.assertEqual(grc_value(p["default"]), -1, block)
            self.assertEqual(sems.frame_of(self.param(block, "frame")["default"], -1).cp_len, cp, block)
        self.assertEqual(sems.target_channel_td().settings().cp_len, cp)
        self.assertEqual(bound_default(sems.frame_sync, "cp_len"), cp)

    def param(self, block, pid):
        return [p for p in self.blocks[block]["parameters"] if p["id"] == pid][0]

    def test_frame_is_one_setting(self):
        # Every block that needs the frame takes one Frame parameter (a string: a preset's name,
        # a frame file or a Variable holding one) and none of the frame's fields by hand.
        fields = {"n_symbols", "n_subcarriers", "bandwidth_hz", "carrier_hz", "symbol_interval_s",
                  "guard_subcarriers"}
        for block in FRAME_BLOCKS:
            p = self.param(block, "frame")
            self.assertEqual((p["label"], p["dtype"], str(p["default"])), ("Frame", "string", "paper"), block)
            ids = {q["id"] for q in self.blocks[block]["parameters"]}
            self.assertFalse(ids & fields, f"{block}: frame fields typed by hand: {sorted(ids & fields)}")
        for block, d in self.blocks.items():
            ids = {q["id"] for q in d.get("parameters", [])}
            if block not in FRAME_BLOCKS:
                self.assertFalse(ids & (fields | {"frame"}), f"{block}: takes a frame field but is not in FRAME_BLOCKS")

    def test_every_parameter_documented(self):
        for block, d in self.blocks.items():
            doc = d.get("documentation", "")
            for p in d.get("parameters", []):
                self.assertIn(f"- {p['label']}: ", doc, f"{block}: parameter {p['id']} ({p['label']}) undocumented")

    def test_checker_catches_a_disagreement(self):
        # The comparison can fail: the old target_channel SNR default (20 dB) against C++'s +inf.
        self.assertFalse(same(grc_value("20.0"), self.cxx["sems_target_channel"]["snr_db"]))
        self.assertTrue(same(grc_value("float('inf')"), self.cxx["sems_target_channel"]["snr_db"]))


if __name__ == "__main__":
    gr_unittest.run(qa_grc_defaults)
