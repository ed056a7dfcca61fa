#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: SigMF recordings. tag_file_sink records a stream as NAME.sigmf-data +
NAME.sigmf-meta; File Source + tag_file_replay give back the same samples and every tag
(key, offset, value bit for bit); the metadata keeps the SigMF specification's rules (checked
by gnuradio.sems.sigmf.problems, whose every rule is shown to fail on a broken file); a
recording of earlier versions (raw file + JSON-lines .tags) converts to the same recording;
bad files are refused naming the file."""
import copy
import json
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio.sems import sigmf
from gnuradio.sems.tag_file import tag_file_replay, tag_file_sink

L = 500  # items per frame of the test streams


def tag(offset, key, value):
    return gr.tag_utils.python_to_tag((offset, pmt.intern(key), value, pmt.intern("src")))


def truth(frame, class_id, class_name, delay_index):
    # The fields of a real sems_truth tag, with the values that need care in JSON: inf snr_db,
    # a None micro_motion_params, the keyword key "class".
    return pmt.to_pmt({"frame": frame, "class": class_id, "class_name": class_name,
                       "delay_index": delay_index, "range_m": 5.0 * delay_index, "snr_db": float("inf"),
                       "micro_motion": "sinusoid", "micro_motion_params": None, "track_id": frame})


def stream_tags():
    """Three frames of L items starting at 100 (the 100 items before belong to no frame), the
    last one cut short by the end of the stream: a tag before the first frame, two tags of one
    key on one item, a tag inside a frame, a non-dict value under sems_truth's key."""
    tags = [tag(7, "sems_note", pmt.intern("before the first frame"))]
    for k, (cid, name) in enumerate([(0, "pedestrian"), (1, "car"), (2, "drone")]):
        start = 100 + k * L
        tags += [tag(start, "sems_frame", pmt.from_uint64(k)),
                 tag(start, "sems_truth", truth(k, cid, name, 12.625 + k))]
    tags += [tag(100 + L + 3, "burst", pmt.from_double(0.1)), tag(100 + L + 3, "burst", pmt.from_long(-2)),
             tag(100 + 2 * L + 9, "sems_truth", pmt.from_double(1.5))]
    return tags


def comparable(tags):
    """(offset, key, serialized value): equal only for the same tag bit for bit."""
    return sorted((t.offset, pmt.symbol_to_string(t.key), pmt.serialize_str(t.value)) for t in tags)


def load(path):
    with open(path) as f:
        return json.load(f)


def record(path, data, tags, vlen=1, **settings):
    tb = gr.top_block()
    item = "complex" if data.dtype == np.complex64 else "float"
    make = blocks.vector_source_c if item == "complex" else blocks.vector_source_f
    src = make(data.reshape(-1).tolist(), False, vlen, tags)
    sink = tag_file_sink(path, item, vlen, **settings)
    tb.connect(src, sink)
    tb.run()
    return sink


def replay(path, data_path, item="complex", vlen=1):
    tb = gr.top_block()
    size = gr.sizeof_gr_complex if item == "complex" else gr.sizeof_float
    rep = tag_file_replay(path, item, vlen)  # a Python block must outlive the run
    snk = blocks.vector_sink_c(vlen) if item == "complex" else blocks.vector_sink_f(vlen)
    tb.connect(blocks.file_source(size * vlen, data_path, False), rep, snk)
    tb.run()
    return np.array(snk.data()), snk.tags()


class qa_sigmf(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name
        rng = np.random.default_rng(7)
        n = 100 + 3 * L - 40  # the third frame is cut short
        self.data = (rng.standard_normal(n) + 1j * rng.standard_normal(n)).astype(np.complex64)
        self.tags = stream_tags()

    def tearDown(self):
        self.dir.cleanup()

    def recorded(self, **settings):
        name = os.path.join(self.d, "rec")
        sink = record(name, self.data, self.tags, **settings)
        self.assertEqual(sink.count, len(self.tags))
        return name, load(name + ".sigmf-meta")

    def test_round_trip_bit_for_bit(self):
        name, _ = self.recorded(sample_rate=30e6, frequency=3e9)
        with open(name + ".sigmf-data", "rb") as f:
            self.assertEqual(f.read(), self.data.astype("<c8").tobytes())  # raw little-endian samples
        for path in (name, name + ".sigmf-meta", name + ".sigmf-data"):
            got, tags = replay(path, name + ".sigmf-data")
            self.assertEqual(got.astype(np.complex64).tobytes(), self.data.tobytes())
            self.assertEqual(comparable(tags), comparable(self.tags))
        want = {(t.offset, pmt.symbol_to_string(t.key)): [] for t in self.tags}
        for t in self.tags:
            want[(t.offset, pmt.symbol_to_string(t.key))].append(t.value)
        for t in tags:
            self.assertTrue(any(pmt.equal(t.value, v) for v in want[(t.offset, pmt.symbol_to_string(t.key))]))

    def test_vectors_of_floats(self):
        # rf32_le, one stream item of vlen values = one sample of vlen channels: offsets unchanged.
        data = np.arange(4 * 60, dtype=np.float32) / 7
        tags = [tag(0, "sems_frame", pmt.from_uint64(0)), tag(30, "sems_frame", pmt.from_uint64(1)),
                tag(59, "x", pmt.from_double(2.0))]
        name = os.path.join(self.d, "vec")
        record(name, data, tags, vlen=4)
        meta = load(name + ".sigmf-meta")
        self.assertEqual(sigmf.problems(meta), [])
        self.assertEqual(meta["global"]["core:datatype"], "rf32_le")
        self.assertEqual(meta["global"]["core:num_channels"], 4)
        self.assertEqual([(a["core:sample_start"], a["core:sample_count"]) for a in meta["annotations"]],
                         [(0, 30), (30, 30)])
        got, out = replay(name, name + ".sigmf-data", "float", 4)
        self.assertEqual(got.astype(np.float32).tobytes(), data.tobytes())
        self.assertEqual(comparable(out), comparable(tags))
        with self.assertRaisesRegex(ValueError, "vec.sigmf-meta: core:num_channels is 4"):
            tag_file_replay(name, "float", 2)

    def test_metadata_keeps_the_specification(self):
        name, meta = self.recorded(sample_rate=30e6, frequency=3e9, description="three frames")
        self.assertEqual(sigmf.problems(meta), [])
        self.assertEqual(sigmf.check(name), name + ".sigmf-meta")
        g = meta["global"]
        self.assertEqual((g["core:datatype"], g["core:version"], g["core:sample_rate"], g["core:description"]),
                         ("cf32_le", sigmf.SPEC_VERSION, 30e6, "three frames"))
        self.assertIn({"name": "sems", "version": "1.0.0", "optional": True}, g["core:extensions"])
        self.assertTrue(g["core:recorder"].startswith("gr-sems"))
        [capture] = meta["captures"]
        self.assertEqual((capture["core:sample_start"], capture["core:frequency"]), (0, 3e9))
        self.assertRegex(capture["core:datetime"], r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{6}Z$")
        # The tag before the first frame: an annotation of one item. The frames: from their
        # sems_frame tag to the next, the last to the end of the data.
        spans = [(a["core:sample_start"], a["core:sample_count"], a["core:label"]) for a in meta["annotations"]]
        self.assertEqual(spans, [(7, 1, "tags"), (100, L, "pedestrian"), (100 + L, L, "car"),
                                 (100 + 2 * L, len(self.data) - 100 - 2 * L, "drone")])
        car = meta["annotations"][2]
        self.assertEqual((car["sems:class_id"], car["sems:class_name"], car["sems:delay_index"],
                          car["sems:range_m"], car["sems:snr_db"], car["sems:micro_motion_params"]),
                         (1, "car", 13.625, 68.125, None, None))
        self.assertNotIn("sems:class", car)  # a keyword: no valid SigMF name
        self.assertEqual((car["core:freq_lower_edge"], car["core:freq_upper_edge"]), (3e9 - 15e6, 3e9 + 15e6))
        self.assertEqual([(t["offset"], t["key"]) for t in car["sems:tags"]],
                         [(100 + L, "sems_frame"), (100 + L, "sems_truth"), (100 + L + 3, "burst"),
                          (100 + L + 3, "burst")])

    def test_frame_length_parameter(self):
        # frame_len 300: the items 300..499 after each frame belong to none; the burst tags at
        # L + 3 (inside the second frame) stay in it, the non-dict truth at 2L + 9 too.
        _, meta = self.recorded(frame_len=300)
        self.assertEqual(sigmf.problems(meta), [])
        spans = [(a["core:sample_start"], a["core:sample_count"]) for a in meta["annotations"]]
        self.assertEqual(spans, [(7, 1), (100, 300), (100 + L, 300), (100 + 2 * L, 300)])
        _, meta = self.recorded(frame_len=L)  # the last frame cut at the end of the data
        spans = [(a["core:sample_start"], a["core:sample_count"]) for a in meta["annotations"]]
        self.assertEqual(spans, [(7, 1), (100, L), (100 + L, L), (100 + 2 * L, len(self.data) - 100 - 2 * L)])
        _, meta = self.recorded(frame_len=2)
        spans = [(a["core:sample_start"], a["core:sample_count"]) for a in meta["annotations"]]
        self.assertEqual(spans, [(7, 1), (100, 2), (100 + L, 2), (100 + L + 3, 1), (100 + 2 * L, 2),
                                 (100 + 2 * L + 9, 1)])
        self.assertEqual(sigmf.problems(meta), [])

    def test_each_rule_can_fail(self):
        _, good = self.recorded(sample_rate=1e6)

        def broken(change):
            meta = copy.deepcopy(good)
            change(meta)
            return sigmf.problems(meta)

        g = lambda m: m["global"]  # noqa: E731
        ann = lambda m: m["annotations"]  # noqa: E731
        cases = {
            "global.core:datatype: required": lambda m: g(m).pop("core:datatype"),
            "core:datatype: required, a SigMF dataset format": lambda m: g(m).update({"core:datatype": "cf32"}),
            "global.core:version: required": lambda m: g(m).pop("core:version"),
            "core:version: required, the specification's version": lambda m: g(m).update({"core:version": 1}),
            "annotations: required": lambda m: m.pop("annotations"),
            "must be sorted by core:sample_start": lambda m: ann(m).reverse(),
            "annotations[1].core:sample_start: required": lambda m: ann(m)[1].pop("core:sample_start"),
            "core:sample_count: must be an integer >= 0": lambda m: ann(m)[1].update({"core:sample_count": -1}),
            "captures[0].core:datetime: must be RFC 3339 in UTC":
                lambda m: m["captures"][0].update({"core:datetime": "2024-01-02T03:04:05+01:00"}),
            "captures[0].core:datetime: not a valid date":
                lambda m: m["captures"][0].update({"core:datetime": "2023-02-29T03:04:05Z"}),
            "namespace 'sems' is not declared": lambda m: g(m).update({"core:extensions": []}),
            "core:extensions[0]: must be an object of exactly":
                lambda m: g(m)["core:extensions"][0].update({"url": "x"}),
            "no C++ or Python keyword": lambda m: ann(m)[1].update({"sems:class": 1}),
            "not a core field of the annotations object": lambda m: ann(m)[1].update({"core:frequency": 1.0}),
            "core:sample_rate: must be between 1 and 1e12": lambda m: g(m).update({"core:sample_rate": 0.5}),
            "core:freq_lower_edge and core:freq_upper_edge go together":
                lambda m: ann(m)[1].pop("core:freq_upper_edge"),
            "core:label: must be of type string": lambda m: ann(m)[1].update({"core:label": 3}),
        }
        for expected, change in cases.items():
            found = broken(change)
            self.assertTrue(any(expected in p for p in found), f"{expected!r} not in {found}")

    def test_converts_a_recording_of_earlier_versions(self):
        raw, side = os.path.join(self.d, "old.c64"), os.path.join(self.d, "old.c64.tags")
        self.data.tofile(raw)
        record(side, self.data, self.tags)  # the JSON-lines sidecar, as earlier versions wrote it
        _, old_tags = replay(side, raw)  # still replays
        self.assertEqual(comparable(old_tags), comparable(self.tags))
        # The command line, in this process (a subprocess would cost a second of imports).
        self.assertEqual(sigmf.main(["convert", raw, "--sample-rate", "30e6", "--frequency", "3e9"]), 0)
        self.assertEqual(sigmf.check(os.path.join(self.d, "old")), os.path.join(self.d, "old.sigmf-meta"))
        got, tags = replay(os.path.join(self.d, "old"), os.path.join(self.d, "old.sigmf-data"))
        self.assertEqual(got.astype(np.complex64).tobytes(), self.data.tobytes())
        self.assertEqual(comparable(tags), comparable(self.tags))
        # The same annotations as the sink's, but no recording time.
        name, meta = self.recorded(sample_rate=30e6, frequency=3e9)
        converted = load(os.path.join(self.d, "old.sigmf-meta"))
        self.assertEqual(converted["annotations"], meta["annotations"])
        self.assertNotIn("core:datetime", converted["captures"][0])
        with self.assertRaisesRegex(ValueError, "old.sigmf-meta exists"):
            sigmf.convert(raw)
        with open(side, "a") as f:
            f.write(json.dumps({"offset": len(self.data), "key": "late", "value": "AA=="}) + "\n")
        with self.assertRaisesRegex(ValueError, "old.c64.tags: tag 'late' at offset %d, past" % len(self.data)):
            sigmf.convert(raw, out=os.path.join(self.d, "new"))

    def test_bad_input(self):
        name, meta = self.recorded()
        meta_path = name + ".sigmf-meta"

        def write(m):
            with open(meta_path, "w") as f:
                json.dump(m, f)

        bad = copy.deepcopy(meta)
        bad["global"]["core:datatype"] = "ci16_le"
        write(bad)
        with self.assertRaisesRegex(ValueError, "rec.sigmf-meta: core:datatype is 'ci16_le'"):
            tag_file_replay(name)
        write(meta)
        with self.assertRaisesRegex(ValueError, "rec.sigmf-meta: core:datatype is 'cf32_le'; a stream of float"):
            tag_file_replay(name, "float")
        bad = copy.deepcopy(meta)
        bad["annotations"][1]["sems:tags"][0]["value"] = "not base64!"
        write(bad)
        with self.assertRaisesRegex(ValueError, r"rec.sigmf-meta: annotations\[1\].sems:tags\[0\].value: not base64"):
            tag_file_replay(name)
        bad["annotations"][1]["sems:tags"][0]["value"] = meta["annotations"][1]["sems:tags"][0]["value"]
        bad["annotations"][1]["sems:tags"][0]["offset"] = len(self.data)
        write(bad)
        with self.assertRaisesRegex(ValueError, r"sems:tags\[0\].offset: must be an item of the data file"):
            tag_file_replay(name)
        bad = copy.deepcopy(meta)
        bad["global"]["core:extensions"].append({"name": "elsewhere", "version": "1.0.0", "optional": False})
        write(bad)
        with self.assertRaisesRegex(ValueError, "needs extension 'elsewhere'"):
            tag_file_replay(name)
        bad = copy.deepcopy(meta)
        del bad["global"]["core:version"]
        write(bad)
        with self.assertRaisesRegex(ValueError, "rec.sigmf-meta: global.core:version: required"):
            tag_file_replay(name)
        with open(meta_path, "w") as f:
            f.write("{")
        with self.assertRaisesRegex(ValueError, "rec.sigmf-meta: not JSON"):
            tag_file_replay(name)
        write(meta)
        with open(name + ".sigmf-data", "ab") as f:
            f.write(b"\0\0\0")
        with self.assertRaisesRegex(ValueError, "rec.sigmf-data: .* no whole number of complex"):
            tag_file_replay(name)
        os.remove(name + ".sigmf-data")
        with self.assertRaisesRegex(ValueError, "rec.sigmf-data: the recording's data file is missing"):
            tag_file_replay(name)
        with self.assertRaisesRegex(ValueError, "cannot read .*nothing.sigmf-meta"):
            tag_file_replay(os.path.join(self.d, "nothing"))
        for settings, what in (({"sample_rate": -1.0}, "sample_rate"), ({"frame_len": -1}, "frame_len"),
                               ({"frequency": float("nan")}, "frequency")):
            with self.assertRaisesRegex(ValueError, "tag_file_sink: " + what):
                tag_file_sink(os.path.join(self.d, "x"), **settings)
        with self.assertRaisesRegex(ValueError, "cannot write .*no_such_dir"):
            tag_file_sink(os.path.join(self.d, "no_such_dir", "x"))


if __name__ == "__main__":
    gr_unittest.run(qa_sigmf)
