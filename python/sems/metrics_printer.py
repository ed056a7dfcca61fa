# SPDX-License-Identifier: GPL-3.0-or-later
"""metrics_printer: prints the running metrics of a SemS sink, one line per message.

Connect a classifier_sink's or delay_estimator_sink's `metrics` port to its `metrics`
input. The line shows what the dict holds: accuracy for a classifier, the delay MAE
for a delay estimator, and the frame counters.
"""
import math
import sys

import pmt
from gnuradio import gr

from .core_python import keys


def format_metrics(label, m):
    """One line for a metrics dict (Python dict with the keys of gnuradio.sems.keys)."""
    parts = ["%-10s" % label, "frames %6d" % m.get(keys.frames, 0)]
    if m.get(keys.frames_skipped, 0):
        parts.append("skipped %d" % m[keys.frames_skipped])
    if keys.accuracy in m:
        acc = m[keys.accuracy]
        parts.append("accuracy " + ("   n/a" if math.isnan(acc) else "%5.1f %%" % (100.0 * acc)))
    if keys.mae_index in m:
        mae, mae_m = m[keys.mae_index], m.get(keys.mae_m, float("nan"))
        parts.append("delay MAE " + ("n/a" if math.isnan(mae) else "%.3f index (%.2f m)" % (mae, mae_m)))
    return "  ".join(parts)


class metrics_printer(gr.basic_block):
    """Prints the running metrics of a SemS sink: each message it receives on `metrics`, one
    line prefixed with `label`."""

    def __init__(self, label="sink"):
        gr.basic_block.__init__(self, name="sems_metrics_printer", in_sig=None, out_sig=None)
        self.label = label
        self.message_port_register_in(pmt.intern(keys.metrics_port))
        self.set_msg_handler(pmt.intern(keys.metrics_port), self.handle)

    def handle(self, msg):
        m = pmt.to_python(msg)
        if isinstance(m, dict):
            print(format_metrics(self.label, m), file=sys.stdout, flush=True)
