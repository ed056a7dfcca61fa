#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""metrics_printer: the line of each kind of metrics dict (classifier, delay estimator, no
score yet, skipped frames), and in a flowgraph one line per metrics message of a real
classifier sink, in order, with the sink's own keys."""
import io
import math
import os
import sys
from contextlib import redirect_stdout

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "testing"))

from gnuradio import blocks, gr, gr_unittest, sems  # noqa: E402
from gnuradio.sems.metrics_printer import format_metrics, metrics_printer  # noqa: E402

import sink_testing as st  # noqa: E402

K = sems.keys


class qa_metrics_printer(gr_unittest.TestCase):

    def test_001_lines(self):
        self.assertEqual(format_metrics("classifier", {K.frames: 500, K.accuracy: 0.9862}),
                         "classifier  frames    500  accuracy  98.6 %")
        self.assertEqual(format_metrics("delay", {K.frames: 1234, K.mae_index: 0.1875, K.mae_m: 0.9375}),
                         "delay       frames   1234  delay MAE 0.188 index (0.94 m)")
        # Before the first truth: n/a, not nan; skipped frames only when there are some.
        self.assertEqual(format_metrics("c", {K.frames: 3, K.frames_skipped: 2, K.accuracy: math.nan}),
                         "c           frames      3  skipped 2  accuracy    n/a")
        self.assertEqual(format_metrics("d", {K.frames: 0, K.frames_skipped: 0, K.mae_index: math.nan}),
                         "d           frames      0  delay MAE n/a")

    def test_002_one_line_per_message_of_a_sink(self):
        bundle = sems.model_bundle.find("classifier")
        _, mask = st.bundle_info(bundle)
        obs, truths = st.channel_frames(mask, 12, seed=3, snr_db=20.0)
        sink = sems.classifier_sink(bundle, mask.size(), batch_size=4, metrics_period=4)
        printer = metrics_printer("classifier")
        tb = gr.top_block()
        src = blocks.vector_source_c(obs.reshape(-1).tolist(), False, mask.size(),
                                     st.frame_tags(list(range(12)), truths))
        col = st.collector(12, 3)
        tb.connect(src, sink)
        tb.connect(blocks.null_source(gr.sizeof_char), col)
        tb.msg_connect((sink, K.metrics_port), (col, K.metrics_port))
        tb.msg_connect((sink, K.result_port), (col, K.result_port))
        tb.msg_connect((sink, K.metrics_port), (printer, K.metrics_port))
        out = io.StringIO()
        with redirect_stdout(out):
            tb.run()
        lines = out.getvalue().splitlines()
        periodic = [m for m in col.metrics if m[K.frames] in (4, 8, 12)][:3]
        self.assertEqual([m[K.frames] for m in periodic], [4, 8, 12])
        self.assertEqual(lines[:3], [format_metrics("classifier", m) for m in periodic])
        self.assertTrue(all(" accuracy " in line for line in lines), lines)


if __name__ == "__main__":
    gr_unittest.run(qa_metrics_printer)
