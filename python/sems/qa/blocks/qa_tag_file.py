#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: tag_file_sink / tag_file_replay with the JSON-lines tag file of earlier versions
(a path ending in .tags): samples through file_sink, tags through the sidecar; the replay from
file_source carries the same tags (keys, values bit-exact, offsets) and the same samples.
SigMF recordings: qa_sigmf.py."""
import os
import tempfile

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio.sems.tag_file import read_tags, tag_file_replay, tag_file_sink


def tag(offset, key, value):
    return gr.tag_utils.python_to_tag((offset, pmt.intern(key), value, pmt.intern("src")))


class qa_tag_file(gr_unittest.TestCase):

    def test_round_trip(self):
        rng = np.random.default_rng(5)
        data = (rng.standard_normal(4000) + 1j * rng.standard_normal(4000)).astype(np.complex64)
        truth = pmt.to_pmt({"class_id": 3, "delay_index": 12.625, "doppler_hz": -41.5})
        tags = [tag(0, "sems_frame", pmt.from_uint64(0)), tag(0, "sems_truth", truth),
                tag(2048, "sems_frame", pmt.from_uint64(1)), tag(3999, "other", pmt.from_double(0.1))]
        with tempfile.TemporaryDirectory() as d:
            raw, side = os.path.join(d, "rec.c64"), os.path.join(d, "rec.tags")
            tb = gr.top_block()
            src = blocks.vector_source_c(data, False, 1, tags)
            tb.connect(src, blocks.file_sink(gr.sizeof_gr_complex, raw))
            rec = tag_file_sink(side)
            tb.connect(src, rec)
            tb.run()
            self.assertEqual(rec.count, 4)

            tb = gr.top_block()
            snk = blocks.vector_sink_c()
            replay = tag_file_replay(side)  # a Python block must outlive the run
            tb.connect(blocks.file_source(gr.sizeof_gr_complex, raw, False), replay, snk)
            tb.run()
            np.testing.assert_array_equal(np.array(snk.data(), dtype=np.complex64), data)
            got = sorted((t.offset, pmt.symbol_to_string(t.key), pmt.serialize_str(t.value)) for t in snk.tags())
            want = sorted((t.offset, pmt.symbol_to_string(t.key), pmt.serialize_str(t.value)) for t in tags)
            self.assertEqual(got, want)

    def test_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.tags")
            with open(bad, "w") as f:
                f.write('{"offset": 1, "key": "k"}\n')
            with self.assertRaisesRegex(ValueError, "bad.tags:1"):
                read_tags(bad)
            with self.assertRaisesRegex(ValueError, "cannot read"):
                tag_file_replay(os.path.join(d, "missing.tags"))
            with self.assertRaisesRegex(ValueError, "item"):
                tag_file_sink(os.path.join(d, "x.tags"), item="int")


if __name__ == "__main__":
    gr_unittest.run(qa_tag_file)
