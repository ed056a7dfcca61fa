#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""sems.frame_of, the one way from what a user types (a preset's name, a frame file, '') to a
frame; and GNU Radio Companion's ports following a block's Frame parameter."""
import json
import os
import tempfile
import unittest

from gnuradio import gr, gr_unittest
from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))


class qa_frame_of(gr_unittest.TestCase):
    def test_preset_name(self):
        fs = sems.frame_of("sdr_2g4_20mhz")
        self.assertEqual(fs, sems.frame_file.find("sdr_2g4_20mhz").frame)
        self.assertEqual((fs.bandwidth_hz, fs.carrier_hz), (20e6, 2.4e9))
        self.assertIn(0, fs.guard_subcarriers)

    def test_frame_file(self):
        fs = sems.frame_of(os.path.join(SOURCE, "models", "frames", "wifi_5g_80mhz.json"))
        self.assertEqual((fs.n_symbols, fs.n_subcarriers, fs.cp_len), (32, 256, 64))

    def test_default(self):
        self.assertEqual(sems.frame_of(""), sems.frame_settings())
        self.assertEqual(sems.frame_of("paper"), sems.frame_settings())
        self.assertEqual(sems.frame_of(), sems.frame_settings())

    def test_object_passes_through(self):
        fs = sems.frame_settings(n_symbols=8, n_subcarriers=16)
        self.assertIs(sems.frame_of(fs), fs)

    def test_unknown_name_is_named(self):
        with self.assertRaises(ValueError) as e:
            sems.frame_of("no_such_frame")
        self.assertIn('frame "no_such_frame"', str(e.exception))
        with self.assertRaises(TypeError):
            sems.frame_of(64)

    def test_prefix_override(self):
        fs = sems.frame_of("paper", 48)
        self.assertEqual(fs.cp_len, 48)
        fs.cp_len = sems.frame_settings().cp_len
        self.assertEqual(fs, sems.frame_settings())  # every other field is the frame's
        self.assertEqual(sems.frame_of("paper", -1), sems.frame_settings())
        with self.assertRaises(ValueError) as e:
            sems.frame_of("paper", 65)  # longer than M
        self.assertIn("'paper'", str(e.exception))

    def test_own_frame_by_name_without_a_variable(self):
        # A frame of one's own in the user's data folder is found by name with no SEMS_FRAMES_PATH
        # (what GNU Radio Companion, started from a menu, needs).
        frame = {"format": "sems.frame", "version": 1, "name": "my_bench",
                 "frame": {"n_symbols": 16, "n_subcarriers": 128}}
        saved = {k: os.environ.get(k) for k in ("XDG_DATA_HOME", "SEMS_FRAMES_PATH")}
        with tempfile.TemporaryDirectory() as home:
            os.makedirs(os.path.join(home, "gr-sems", "models", "frames"))
            with open(os.path.join(home, "gr-sems", "models", "frames", "my_bench.json"), "w") as f:
                json.dump(frame, f)
            try:
                os.environ.pop("SEMS_FRAMES_PATH", None)
                os.environ["XDG_DATA_HOME"] = home
                self.assertEqual(sems.frame_of("my_bench").n_subcarriers, 128)
            finally:
                for k, v in saved.items():
                    if v is None:
                        os.environ.pop(k, None)
                    else:
                        os.environ[k] = v


class qa_grc_frame_ports(gr_unittest.TestCase):
    """GRC evaluates a block's ports from its Frame (a name, or a Variable holding one)."""

    @classmethod
    def setUpClass(cls):
        os.environ["GRC_BLOCKS_PATH"] = os.path.join(SOURCE, "grc")
        from gnuradio.grc.core.platform import Platform
        cls.platform = Platform(name="qa_frame_of", prefs=gr.prefs(), version=gr.version(),
                                version_parts=(gr.major_version(), gr.api_version(), gr.minor_version()))
        cls.platform.build_library()

    def flowgraph(self, blocks, variables=()):
        fg = self.platform.make_flow_graph()
        data = {"metadata": {"file_format": 1},
                "options": {"parameters": {"id": "qa", "generate_options": "no_gui"}, "states": {}},
                "blocks": [{"name": n, "id": "variable", "parameters": {"value": v}, "states": {}}
                           for n, v in variables]
                + [{"name": n, "id": i, "parameters": p, "states": {}} for n, i, p in blocks],
                "connections": []}
        fg.import_data(data)
        fg.rewrite()
        fg.validate()
        return {b.name: b for b in fg.blocks}

    def test_ports_follow_the_frame(self):
        pos = {"mask_source": "positions", "pilot_positions": "[0]"}
        blocks = self.flowgraph([
            ("mapper", "sems_pilot_mapper", dict(pos, frame="wifi_5g_80mhz")),
            ("channel", "sems_target_channel", {"frame": "wifi_5g_80mhz"}),
            ("tx", "sems_ofdm_tx", {"frame": "frame_var"}),
            ("rd", "sems_range_doppler_map", dict(pos, n_pilots="1", frame="frame_var")),
            ("default", "sems_pilot_extractor", dict(pos, n_pilots="1")),
        ], variables=[("frame_var", "'wifi_5g_80mhz'")])
        vlen = [blocks["mapper"].sources[0].vlen, blocks["channel"].sinks[0].vlen,
                blocks["tx"].sinks[0].vlen, blocks["rd"].sources[0].vlen, blocks["default"].sinks[0].vlen]
        for name, b in blocks.items():  # no parameter, port or assert failed to evaluate (the ports are unconnected)
            errors = [e for e in b.get_error_messages() if "not connected" not in e]
            self.assertEqual(errors, [], name)
        # the mapper and channel by name, OFDM Tx through the Variable, the map N*M, the extractor's default (paper)
        self.assertEqual(vlen, [256, 256, 256, 32 * 256, 64])
        # The generated code reads the frame through frame_of, the Variable by its name.
        self.assertIn("sems.frame_of('wifi_5g_80mhz')", blocks["mapper"].templates.render("make"))
        self.assertIn("sems.frame_of(frame_var, (-1)).cp_len", blocks["tx"].templates.render("make"))


if __name__ == "__main__":
    gr_unittest.run(qa_frame_of)  # runs every test case of this file
