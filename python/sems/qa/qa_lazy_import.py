#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: `import gnuradio.sems` stays light. A flowgraph of mapper -> channel ->
extractor runs without LibTorch mapped into the process; the first use of a learning
name loads it; the lazy name lists match what the extensions bind."""
import os
import subprocess
import sys

from gnuradio import gr_unittest

# Runs in a fresh interpreter, so nothing else in this test has loaded LibTorch.
CORE_CHAIN = r"""
import numpy as np
from gnuradio import blocks, gr, sems

def torch_mapped():
    with open("/proc/self/maps") as f:
        return sorted({l.split()[-1] for l in f if "libtorch" in l or "libc10" in l})

N, M, POS = 4, 8, [0, 3, 9, 17]
tb = gr.top_block()
src = blocks.vector_source_c(np.ones(3 * (N * M - len(POS)), np.complex64).tolist())
mapper = sems.pilot_mapper(pilot_positions=POS, n_symbols=N, n_subcarriers=M)
channel = sems.target_channel(seed=3, n_symbols=N, n_subcarriers=M, bandwidth_hz=M * 468.75e3)
extractor = sems.pilot_extractor(pilot_positions=POS, n_symbols=N, n_subcarriers=M)
sink = blocks.vector_sink_c(len(POS))
tb.connect(src, mapper, channel, extractor, sink)
tb.run()
assert len(sink.data()) == 3 * len(POS), len(sink.data())
print("core-chain-torch:", torch_mapped())
sems.classifier_sink  # the first learning name loads LibTorch
print("after-learning-name-torch:", bool(torch_mapped()))
"""


def run_python(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ)
    if out.returncode != 0:
        raise AssertionError("subprocess failed:\n" + out.stdout + out.stderr)
    return out.stdout


class qa_lazy_import(gr_unittest.TestCase):

    def test_001_core_chain_runs_without_libtorch(self):
        out = run_python(CORE_CHAIN)
        self.assertIn("core-chain-torch: []", out)
        self.assertIn("after-learning-name-torch: True", out)

    def test_002_lazy_names_match_the_extensions(self):
        from gnuradio import sems
        from gnuradio.sems import baselines_python, learning_python
        for module, names in ((learning_python, "learning_python"), (baselines_python, "baselines_python")):
            bound = {n for n in dir(module) if not n.startswith("_")}
            self.assertEqual(bound, set(sems._LAZY_MODULES[names]), names)
        # Every lazy name resolves, and unknown names still raise AttributeError.
        for name in sems._LAZY_NAMES:
            self.assertIsNotNone(getattr(sems, name))
        with self.assertRaises(AttributeError):
            sems.no_such_name  # noqa: B018
        from gnuradio.sems import delay_crb  # `from ... import` goes through __getattr__ too
        self.assertIs(delay_crb, sems.delay_crb)


if __name__ == "__main__":
    gr_unittest.run(qa_lazy_import)
