# SPDX-License-Identifier: GPL-3.0-or-later
"""Test helpers shared by qa_classifier_sink.py and qa_delay_estimator_sink.py.

Not part of the installed package: the qa files put this folder on sys.path.

- tiny_bundle(): trains a tiny bundle with the build tree's sems_train (fixed seed,
  seconds), or uses a shipped one when SEMS_TEST_BUNDLE_<TASK> points at it.
- channel_frames(): pilot observations and truth dicts from the core channel model.
- run_sink(): streams frames with sems_frame / sems_truth tags through a sink and
  collects every result and metrics message.

Why the collector has a stream input: GNU Radio calls a block's stop() only after it
has told its message subscribers it is done, and a subscriber without stream inputs
(message_debug) exits on that notice - so it would miss what the sink sends from
stop() (the partial last batch, the final metrics). The collector is kept alive by a
null source and ends itself a moment after it holds every message the test expects (so
an extra message is seen too), or at a deadline, so a missing one fails the test instead
of hanging it.
"""
import json
import os
import shutil
import subprocess
import tempfile
import time

import numpy as np
import pmt
from gnuradio import blocks, gr
from gnuradio import sems

SOURCE_DIR = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
BUILD_DIR = os.environ.get("SEMS_BUILD_DIR", "")

# Tiny training settings: a few seconds on one core. Accuracy does not matter here,
# only that a real bundle loads and decodes.
_TINY_COMMON = ["--frames", "600", "--epochs", "1", "--decoder-epochs", "0", "--batch", "64", "--pilots", "8",
                "--seed", "7", "--threads", "1", "--snr", "20", "--eval-snr", "20", "--width", "4", "--depth", "1",
                "--quiet"]
TINY_TRAIN_ARGS = {
    "classify": _TINY_COMMON + ["--hidden", "16"],
    "delay": _TINY_COMMON,
}


def sems_train_path():
    return os.path.join(BUILD_DIR, "apps", "sems_train")


def tiny_bundle(task, workdir):
    """A bundle directory for `task` ('classify' or 'delay')."""
    env_dir = os.environ.get("SEMS_TEST_BUNDLE_" + task.upper())
    if env_dir:
        return env_dir
    out = os.path.join(workdir, task + "_tiny")
    cmd = [sems_train_path(), "--task", task, "--out", out] + TINY_TRAIN_ARGS[task]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    if proc.returncode != 0:
        raise RuntimeError("tiny training failed: %s\n%s" % (" ".join(cmd), proc.stdout[-3000:]))
    return out


def bundle_info(bundle_dir):
    with open(os.path.join(bundle_dir, "bundle.json")) as f:
        bundle = json.load(f)
    mask = sems.pilot_mask.load(os.path.join(bundle_dir, "mask.json"))
    return bundle, mask


def copy_bundle(bundle_dir, workdir, name, edit=None):
    """A copy of a bundle, with bundle.json changed by edit(dict) when given."""
    out = os.path.join(workdir, name)
    shutil.rmtree(out, ignore_errors=True)
    shutil.copytree(bundle_dir, out)
    if edit:
        path = os.path.join(out, "bundle.json")
        with open(path) as f:
            j = json.load(f)
        edit(j)
        with open(path, "w") as f:
            json.dump(j, f)
    return out


def channel_frames(mask, count, seed, snr_db, classes=None):
    """(obs, truths): count x N_p pilot observations (complex64) of random single-target
    scenes at snr_db, and the truth dict of each frame."""
    fs = sems.frame_settings(n_symbols=mask.n_symbols(), n_subcarriers=mask.n_subcarriers())
    spec = sems.random_spec() if classes is None else sems.random_spec(classes=classes)
    cm = sems.channel_model(fs, sems.scene.random(spec), seed)
    h, truths = cm.generate(count, 0)
    pos = np.array(mask.positions())  # (n, m) pairs in mask order
    obs = np.ascontiguousarray(h[:, pos[:, 0], pos[:, 1]]).astype(np.complex64)
    if mask.equal_power():
        cm.add_noise(obs, snr_db)
    else:  # pilot k's noise is scaled by mask.noise_scale(k) = 1/sqrt(p_k)
        noise = np.zeros_like(obs)
        cm.add_noise(noise, snr_db)
        obs += noise * np.array([mask.noise_scale(k) for k in range(mask.size())], dtype=np.float32)
    for t in truths:
        t[sems.keys.snr_db] = float(snr_db)
    return obs, truths


class collector(gr.sync_block):
    """Stores result and metrics messages; ends the flowgraph once it has `n_results`
    results and `n_metrics` metrics messages, or at the deadline."""

    def __init__(self, n_results, n_metrics, deadline_s=120.0, grace_s=0.1):
        gr.sync_block.__init__(self, "sems_test_collector", in_sig=[np.uint8], out_sig=None)
        self.results, self.metrics = [], []
        self.n_results, self.n_metrics = n_results, n_metrics
        self.deadline = time.monotonic() + deadline_s
        self.grace_s = grace_s  # keeps listening this long after the expected count: extras show up
        self.complete_at = None
        # GNU Radio's Python gateway dispatches to handlers by method name: no lambdas.
        self.message_port_register_in(pmt.intern(sems.keys.result_port))
        self.set_msg_handler(pmt.intern(sems.keys.result_port), self.on_result)
        self.message_port_register_in(pmt.intern(sems.keys.metrics_port))
        self.set_msg_handler(pmt.intern(sems.keys.metrics_port), self.on_metrics)

    def on_result(self, msg):
        self.results.append(pmt.to_python(msg))

    def on_metrics(self, msg):
        self.metrics.append(pmt.to_python(msg))

    def work(self, input_items, output_items):
        now = time.monotonic()
        if self.complete_at is None and len(self.results) >= self.n_results and len(self.metrics) >= self.n_metrics:
            self.complete_at = now
        if (self.complete_at is not None and now - self.complete_at > self.grace_s) or now > self.deadline:
            return -1
        time.sleep(0.002)  # messages are handled between work calls
        return len(input_items[0])


def frame_tags(indices, truths):
    """sems_frame / sems_truth tags for item i (None entries: no tag)."""
    tags = []
    for i, (idx, truth) in enumerate(zip(indices, truths)):
        if idx is not None:
            tags.append(gr.tag_utils.python_to_tag((i, pmt.intern(sems.keys.frame_tag), pmt.from_uint64(int(idx)),
                                                    pmt.intern("test"))))
        if truth is not None:
            tags.append(gr.tag_utils.python_to_tag((i, pmt.intern(sems.keys.truth_tag), pmt.to_pmt(truth),
                                                    pmt.intern("test"))))
    return tags


def run_sink(sink, obs, indices=None, truths=None, n_results=None, n_metrics=0):
    """Streams obs (count x N_p) with tags through `sink`; returns (results, metrics) as
    Python dicts. n_results defaults to one per finite frame."""
    count, n_p = obs.shape
    indices = indices if indices is not None else [None] * count
    truths = truths if truths is not None else [None] * count
    if n_results is None:
        n_results = int(np.sum(np.all(np.isfinite(obs.view(np.float32)), axis=1)))
    tb = gr.top_block()
    src = blocks.vector_source_c(obs.reshape(-1).tolist(), False, n_p, frame_tags(indices, truths))
    col = collector(n_results, n_metrics)
    tb.connect(src, sink)
    tb.connect(blocks.null_source(gr.sizeof_char), col)
    tb.msg_connect((sink, sems.keys.result_port), (col, sems.keys.result_port))
    tb.msg_connect((sink, sems.keys.metrics_port), (col, sems.keys.metrics_port))
    tb.run()
    return col.results, col.metrics


def reference_decoder(bundle_dir, threads=1):
    """bundle_decoder straight from the bindings, when they offer it (else None)."""
    if not hasattr(sems, "bundle_decoder") or not hasattr(sems, "model_bundle"):
        return None
    return sems.bundle_decoder(sems.model_bundle.load(bundle_dir), threads)


def workdir(prefix):
    return tempfile.mkdtemp(prefix=prefix)
