#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The block reference: one page per GNU Radio Companion block, generated from its sources.

    block_reference.py SOURCE_DIR --write          write docs/reference/blocks/<block id>.md and README.md
    block_reference.py SOURCE_DIR --check          exit 1 on any problem below (CTest block_reference)
    block_reference.py SOURCE_DIR --check --no-run the same without running the examples

Every fact on a page comes from one source, and the page says which:
  grc/sems_*.block.yml     the label, id, ports (item type, vector length), parameters (label,
                           id, type, default, options), the asserts GRC checks, and the
                           `documentation:` text GRC shows: prose, then three lists (below)
  include/gnuradio/sems/blocks/*.h, include/gnuradio/sems/learning/sinks/*.h
                           the purpose: the Doxygen \\brief of the block's class
  python/sems/*.py         the purpose of a block written in Python: its class docstring's
                           first paragraph
  include/gnuradio/sems/core/common/tags.h
                           what each stream-tag key carries
  EXAMPLES below           each block's minimal flowgraph and its Python
  examples/*.grc           the shipped flowgraphs that use the block

The lists of `documentation:` (one item per line; an indented line continues the item):
  Ports:                   one item per port, named by its label (or a message port's id):
  - <port>: <rate>; <what it carries>
  Tags:                    or the single line "Tags: none (<why>)."
  - reads|writes|passes <key>: <how>       (<key>: a stream-tag key of tags.h, or
                                           "every tag ...", "other tags")
  Parameters:              one item per parameter, named by its GRC label:
  - <label>: <description>[ Unit: <unit>.][ Range: <range>.]

Rules: --check fails on each of these, naming the file:
  - every block of grc/sems_*.block.yml passes GRC's own schema check (no key GRC ignores) and
    has an example, a page and a row of the index; README.md's block table links its row to it;
  - every port has a Ports item whose rate says "per" or "every" (per frame, per sample, ...);
    every Ports, Tags and Parameters item names a port, a tag key, a parameter of the block;
  - every parameter has a Parameters item and a default;
  - a parameter of a numeric type (int, real, float, complex and their vectors) states its
    unit: in its label's parentheses (Hz, dB, dBc/Hz, s, S/s, samples, frames, items) or as "Unit:"
    ("Unit: none." for a pure number: a seed, a weight), not in both; and its range: an
    assert of the YAML that bounds it alone (n_symbols >= 1), or "Range:", not both. An enum
    or bool ranges over its options and has no unit;
  - the pages in the repository equal the generated ones, and every example runs (one
    process for all, a few frames each).
"""
import argparse
import ast
import difflib
import glob
import os
import re
import subprocess
import sys
import tempfile

import yaml

OUT = os.path.join("docs", "reference", "blocks")
HEADER_DIRS = (os.path.join("include", "gnuradio", "sems", "blocks"),
               os.path.join("include", "gnuradio", "sems", "learning", "sinks"))
TAGS_H = os.path.join("include", "gnuradio", "sems", "core", "common", "tags.h")
NUMERIC = {"int", "real", "float", "complex", "int_vector", "real_vector", "float_vector", "complex_vector"}
LABEL_UNITS = {"Hz", "dB", "dBc/Hz", "s", "S/s", "samples", "frames", "items"}
SECTIONS = ("Ports", "Tags", "Parameters")
ITEM_TYPES = {"complex": "complex (gr_complex)", "float": "float", "int": "int", "short": "short", "byte": "byte"}
MARK = "block_reference"  # <!-- block_reference --> ... <!-- /block_reference -->: generated text

# Each block's minimal flowgraph: the chain as GRC draws it, and the same in Python. Every
# snippet stands alone (a user may paste it) and runs in a second or less; --check runs them
# all. Index order is this order: transmitter, channels, receiver, sinks, tools.
EXAMPLES = {
    "sems_pilot_mapper": ("Noise Source (data) → **SemS Pilot Mapper** → Head → Vector Sink", '''
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]  # one pilot per symbol, N = 32, M = 64
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)  # any unit-power complex symbols
mapper = sems.pilot_mapper(pilot_positions=positions, pilot_power=2.0)
head = blocks.head(gr.sizeof_gr_complex * 64, 4 * 32)  # 4 frames of 32 OFDM symbols
sink = blocks.vector_sink_c(64)
tb.connect(data, mapper, head, sink)
tb.run()
print(mapper.n_pilots(), "pilots and", mapper.data_per_frame(), "data symbols per frame;",
      sum(1 for t in sink.tags() if str(t.key) == sems.keys.frame_tag), "frames tagged")
'''),
    "sems_mimo_pilot_mapper": ("Noise Source (data) → **SemS MIMO Pilot Mapper** (2 outputs) → SemS Target Channel (2 in, 4 out) → SemS Pilot Extractor → Head → Vector Sink", '''
import json, os, tempfile
from gnuradio import analog, blocks, gr, sems

fs = sems.frame_settings()  # the paper's frame; mimo2x4_3g: 4 receive, 2 transmit elements
mask = sems.mimo_mask.time_division(sems.pilot_mask.from_pattern("random", fs, 32, 1), 2)
path = os.path.join(tempfile.mkdtemp(), "mimo_mask.json")
mask.save(path)  # or a learned one: sems_mimo_mask --array mimo2x4_3g --out mimo_mask.json
scene = json.dumps({"format": "sems.scene", "version": 1, "array": "mimo2x4_3g",
                    "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8, "azimuth_rad": 0.3}]})
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.mimo_pilot_mapper(path, 2)
channel = sems.target_channel(scene, snr_db=20.0, seed=1, n_receive=4, n_transmit=2)
extractor = sems.pilot_extractor(mask_file=path, n_elements=4)
head = blocks.head(gr.sizeof_gr_complex * 4 * 32, 4)  # 4 frames of 4 x 32 pilot observations
sink = blocks.vector_sink_c(4 * 32)
tb.connect(data, mapper)
for j in range(2):
    tb.connect((mapper, j), (channel, j))
for k in range(4):
    tb.connect((channel, k), (extractor, k))
tb.connect(extractor, head, sink)
tb.run()
ml = sems.mimo_ml_angle_estimator(sems.array_geometry.find("mimo2x4_3g"), mask, fs, 0.0)
frames = [sink.data()[i * 128:(i + 1) * 128] for i in range(4)]
print("azimuth per frame:", [round(ml.estimate(f).azimuth_rad, 3) for f in frames], "rad (truth 0.3)")
'''),
    "sems_target_channel": ("Noise Source (data) → SemS Pilot Mapper → **SemS Target Channel** → Head → Vector Sink", '''
import pmt
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
channel = sems.target_channel(heading="any", snr_db=10.0, seed=1)  # random scenes, paper's classes
head = blocks.head(gr.sizeof_gr_complex * 64, 4 * 32)
sink = blocks.vector_sink_c(64)
tb.connect(data, mapper, channel, head, sink)
tb.run()
for tag in sink.tags():
    if str(tag.key) == sems.keys.truth_tag:
        truth = pmt.to_python(tag.value)
        print(truth["frame"], truth["class_name"], "%.1f m" % truth["range_m"], "%.1f m/s" % truth["velocity_mps"])
'''),
    "sems_target_channel_td": ("SemS Pilot Mapper → SemS OFDM Tx → **SemS Target Channel (time domain)** → SemS OFDM Rx → SemS Pilot Extractor → Vector Sink", '''
import pmt
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
cp = 48  # covers the class table's ranges (docs/reference/time_domain.md)
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 3 * 32)
channel = sems.target_channel_td(snr_db=20.0, seed=1, cp_len=cp)
extractor = sems.pilot_extractor(pilot_positions=positions)
sink = blocks.vector_sink_c(32)
tb.connect(data, mapper, head, sems.ofdm_tx(64, cp), channel, sems.ofdm_rx(64, cp), extractor, sink)
tb.run()
truths = [pmt.to_python(t.value) for t in sink.tags() if str(t.key) == sems.keys.truth_tag]
print(len(sink.data()) // 32, "frames;", ", ".join("%s at %.1f m" % (t["class_name"], t["range_m"]) for t in truths))
'''),
    "sems_radio_front_end": ("SemS Pilot Mapper → SemS OFDM Tx → **SemS Radio Front End (time domain)** → SemS OFDM Rx → Vector Sink", '''
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 2 * 32)
# The ideal radio with a few impairments: leakage 30 dB over the echo, a 10-bit converter.
radio = sems.radio_front_end(snr_db=20.0, seed=1, leakage_db=30.0, adc_enob=10.0)
sink = blocks.vector_sink_c(64)
tb.connect(data, mapper, head, sems.ofdm_tx(), radio, sems.ofdm_rx(), sink)
tb.run()
print(len(sink.data()) // 64, "symbols; converter full scale per rail %.2f" % radio.full_scale())
'''),
    "sems_phase_noise_source": ("**SemS Phase Noise Source** → Head → Vector Sink (the phase in numpy)", '''
import numpy as np
from gnuradio import blocks, gr, sems

fs = 30e6
tb = gr.top_block()
osc = sems.phase_noise_source(sample_rate_hz=fs, dbc_hz=-80.0, offset_hz=100e3, seed=1)
head = blocks.head(gr.sizeof_gr_complex, 30000)  # 1 ms
sink = blocks.vector_sink_c()
tb.connect(osc, head, sink)
tb.run()
phase = np.unwrap(np.angle(np.array(sink.data())))
print("phase after 1 ms: %.4f rad (diffusion D = %.1f rad^2/s)" % (phase[-1], osc.diffusion()))
'''),
    "sems_ofdm_tx": ("SemS Pilot Mapper → **SemS OFDM Tx (IFFT + CP)** → Head → Vector Sink", '''
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
tx = sems.ofdm_tx(n_subcarriers=64, cp_len=16)
head = blocks.head(gr.sizeof_gr_complex, 2 * 32 * (64 + 16))  # 2 frames of samples
sink = blocks.vector_sink_c()
tb.connect(data, mapper, tx, head, sink)
tb.run()
print(len(sink.data()), "samples; frame tags at", [t.offset for t in sink.tags() if str(t.key) == sems.keys.frame_tag])
'''),
    "sems_ofdm_rx": ("SemS Pilot Mapper → SemS OFDM Tx → **SemS OFDM Rx (CP removal + FFT)** → Vector Sink", '''
import numpy as np
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 2 * 32)
sent, received = blocks.vector_sink_c(64), blocks.vector_sink_c(64)
tb.connect(data, mapper, head, sent)
tb.connect(head, sems.ofdm_tx(64, 16), sems.ofdm_rx(64, 16), received)
tb.run()
print("largest difference after Tx and Rx: %.1e" % np.max(np.abs(np.array(sent.data()) - np.array(received.data()))))
'''),
    "sems_frame_sync": ("SemS Pilot Mapper → SemS OFDM Tx → Delay → Add (noise) → **SemS Frame Sync** → SemS OFDM Rx → SemS Pilot Extractor → Vector Sink", '''
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 8 * 32)
offset = blocks.delay(gr.sizeof_gr_complex, 1234)  # samples the receiver does not know about
noise, add = analog.noise_source_c(analog.GR_GAUSSIAN, 0.3, 1), blocks.add_cc()  # about 10 dB
sync = sems.frame_sync(pilot_positions=positions, search_frames=4)
extractor = sems.pilot_extractor(pilot_positions=positions)
sink = blocks.vector_sink_c(32)
tb.connect(data, mapper, head, sems.ofdm_tx(), offset, (add, 0))
tb.connect(noise, (add, 1))
tb.connect(add, sync, sems.ofdm_rx(), extractor, sink)
tb.run()
print("frame start found at sample", sync.offset(), "of", sync.frame_len(), "per frame;", len(sink.data()) // 32, "frames out")
'''),
    "sems_cfo_corrector": ("SemS Pilot Mapper → SemS OFDM Tx → Multiply (frequency offset) → **SemS CFO Corrector** → Null Sink", '''
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
fs, cfo_hz = 30e6, 50e3  # about a tenth of the subcarrier spacing
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 4 * 32)
offset = analog.sig_source_c(fs, analog.GR_COS_WAVE, cfo_hz, 1.0)
mix = blocks.multiply_cc()
corrector = sems.cfo_corrector(symbols=32)
sink = blocks.null_sink(gr.sizeof_gr_complex)
tb.connect(data, mapper, head, sems.ofdm_tx(), (mix, 0))
tb.connect(offset, (mix, 1))
tb.connect(mix, corrector, sink)
tb.run()
print("offset %.0f Hz, estimated %.0f Hz over %d windows" % (cfo_hz, corrector.cfo() * fs / 64, corrector.windows()))
'''),
    "sems_leakage_canceller": ("SemS OFDM Tx → SemS Radio Front End → **SemS Leakage Canceller** (rx); SemS OFDM Tx → **SemS Leakage Canceller** (tx) → Vector Sink", '''
import numpy as np
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 4 * 32)
tx = sems.ofdm_tx()
radio = sems.radio_front_end(snr_db=30.0, seed=1, leakage_db=30.0)  # sample-aligned with tx
canceller = sems.leakage_canceller(window=32 * 80)  # one frame per fit
before, after = blocks.vector_sink_c(), blocks.vector_sink_c()
tb.connect(data, mapper, head, tx, radio, (canceller, 0))
tb.connect(tx, (canceller, 1))
tb.connect(radio, before)
tb.connect(canceller, after)
tb.run()
power = lambda x: 10 * np.log10(np.mean(np.abs(np.array(x.data())) ** 2))
print("received %.1f dB, after the canceller %.1f dB" % (power(before), power(after)))
'''),
    "sems_pilot_extractor": ("SemS Pilot Mapper → SemS Target Channel → **SemS Pilot Extractor** → Vector Sink", '''
import numpy as np
from gnuradio import analog, blocks, gr, sems

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
channel = sems.target_channel(snr_db=20.0, seed=1)
head = blocks.head(gr.sizeof_gr_complex * 64, 4 * 32)
extractor = sems.pilot_extractor(pilot_positions=positions)
sink = blocks.vector_sink_c(32)  # one vector of N_p = 32 pilot observations per frame
tb.connect(data, mapper, channel, head, extractor, sink)
tb.run()
pilots = np.array(sink.data()).reshape(-1, 32)
print(pilots.shape[0], "frames; mean pilot power %.2f" % np.mean(np.abs(pilots) ** 2))
'''),
    "sems_classifier_sink": ("SemS Pilot Mapper → SemS Target Channel → SemS Pilot Extractor → **SemS Classifier Sink**", '''
import os
from gnuradio import analog, blocks, gr, sems

bundle = sems.model_bundle.find("classifier")  # a shipped bundle, found by name
mask = os.path.join(bundle, "mask.json")  # the pilots the bundle was trained on
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(mask_file=mask)
channel = sems.target_channel(snr_db=20.0, seed=1)
head = blocks.head(gr.sizeof_gr_complex * 64, 8 * 32)
extractor = sems.pilot_extractor(mask_file=mask)
sink = sems.classifier_sink(bundle, extractor.n_pilots(), batch_size=4)
tb.connect(data, mapper, channel, head, extractor, sink)
tb.run()
print(sink.frames(), "frames, accuracy %.2f over" % sink.accuracy(), sink.class_names())
'''),
    "sems_delay_estimator_sink": ("SemS Pilot Mapper → SemS Target Channel → SemS Pilot Extractor → **SemS Delay Estimator Sink**", '''
import os
from gnuradio import analog, blocks, gr, sems

bundle = sems.model_bundle.find("delay_single")
mask = os.path.join(bundle, "mask.json")
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(mask_file=mask)
channel = sems.target_channel(snr_db=20.0, seed=1)
head = blocks.head(gr.sizeof_gr_complex * 64, 8 * 32)
extractor = sems.pilot_extractor(mask_file=mask)
sink = sems.delay_estimator_sink(bundle, extractor.n_pilots(), batch_size=4)
tb.connect(data, mapper, channel, head, extractor, sink)
tb.run()
print(sink.frames(), "frames, delay MAE %.2f index (%.2f m)" % (sink.mae_index(), sink.mae_m()))
'''),
    "sems_metrics_printer": ("... → SemS Classifier Sink (metrics) → **SemS Metrics Printer**", '''
import os
import time
from gnuradio import analog, blocks, gr, sems
from gnuradio.sems.metrics_printer import metrics_printer

bundle = sems.model_bundle.find("classifier")
mask = os.path.join(bundle, "mask.json")
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(mask_file=mask)
channel = sems.target_channel(snr_db=20.0, seed=1)
extractor = sems.pilot_extractor(mask_file=mask)
throttle = blocks.throttle(gr.sizeof_gr_complex * 64, 32 * 100)  # 100 frames per second
sink = sems.classifier_sink(bundle, extractor.n_pilots(), batch_size=4, metrics_period=10)
printer = metrics_printer("classifier")  # a Python block: keep a reference
tb.connect(data, mapper, channel, throttle, extractor, sink)
tb.msg_connect(sink, "metrics", printer, "metrics")
tb.start()
time.sleep(0.5)  # about 50 frames: a line every 10
tb.stop()
tb.wait()
'''),
    "sems_range_doppler_map": ("SemS Pilot Mapper (every cell a pilot) → SemS Target Channel → SemS Pilot Extractor → **SemS Range-Doppler Map** → Vector Sink", '''
import numpy as np
import pmt
from gnuradio import blocks, gr, sems

n, m = 32, 64
grid = list(range(n * m))  # the full grid: pilots only, the mapper needs no data
tb = gr.top_block()
mapper = sems.pilot_mapper(pilot_positions=grid)
channel = sems.target_channel(classes=["car"], seed=1)
head = blocks.head(gr.sizeof_gr_complex * m, 2 * n)
extractor = sems.pilot_extractor(pilot_positions=grid)
rd = sems.range_doppler_map(pilot_positions=grid)
sink = blocks.vector_sink_f(n * m)
tb.connect(mapper, channel, head, extractor, rd, sink)
tb.run()
first = np.array(sink.data()[:n * m]).reshape(n, m)
d, q = np.unravel_index(np.argmax(first), first.shape)
truth = [pmt.to_python(t.value) for t in sink.tags() if str(t.key) == sems.keys.truth_tag][0]
print("peak at Doppler bin %d, delay index %d; truth: delay index %.1f" % (d - n // 2, q, truth["delay_index"]))
'''),
    "sems_position_sink": ("SemS Pilot Mapper → SemS Target Channel (8 outputs) → SemS Pilot Extractor (8 inputs) → **SemS Position Sink**", '''
import json
import os
from gnuradio import analog, blocks, gr, sems

bundle = sems.model_bundle.find("position_ula8")
mask = os.path.join(bundle, "mask.json")
scene = {"format": "sems.scene", "version": 1, "fading": "none", "array": "ula8_3g",
         "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8, "azimuth_rad": 0.4}]}
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(mask_file=mask)
channel = sems.target_channel(scene=json.dumps(scene), snr_db=20.0, seed=1, n_receive=8)
extractor = sems.pilot_extractor(mask_file=mask, n_elements=8)
sink = sems.position_sink(bundle, 8, extractor.n_pilots(), batch_size=4)
head = blocks.head(gr.sizeof_gr_complex * 64, 8 * 32)  # 8 frames of 32 symbols
tb.connect(data, mapper, head, channel)
for k in range(8):
    tb.connect((channel, k), (extractor, k))
tb.connect(extractor, sink)
tb.run()
print(sink.frames(), "frames, azimuth RMSE %.2f mrad, delay MAE %.2f index" % (1e3 * sink.rmse_azimuth_rad(), sink.mae_index()))
'''),
    "sems_range_angle_map": ("SemS Pilot Mapper (every cell a pilot) → SemS Target Channel (8 outputs) → SemS Pilot Extractor (8 inputs) → **SemS Range-Angle Map** → Vector Sink", '''
import json
import math
import numpy as np
from gnuradio import blocks, gr, sems

n, m = 32, 64
grid = list(range(n * m))  # the full grid: pilots only, the mapper needs no data
ula = {"receive": {"ula": {"elements": 8, "spacing_m": 0.05}}}
scene = {"format": "sems.scene", "version": 1, "array": ula,
         "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8, "azimuth_rad": 0.4}]}
tb = gr.top_block()
mapper = sems.pilot_mapper(pilot_positions=grid)
head = blocks.head(gr.sizeof_gr_complex * m, 2 * n)
channel = sems.target_channel(scene=json.dumps(scene), seed=1, n_receive=8)
extractor = sems.pilot_extractor(pilot_positions=grid, n_elements=8)
ra = sems.range_angle_map(json.dumps(dict(ula, format="sems.array", version=1)), pilot_positions=grid)
sink = blocks.vector_sink_f(64 * m)
tb.connect(mapper, head, channel)
for k in range(8):
    tb.connect((channel, k), (extractor, k))
tb.connect(extractor, ra, sink)
tb.run()
first = np.array(sink.data()[:64 * m]).reshape(64, m)
a, q = np.unravel_index(np.argmax(first), first.shape)
print("peak at azimuth %.2f rad, delay index %d; truth: 0.40 rad, delay index 12" % (-math.pi / 2 + math.pi * (a + 0.5) / 64, q))
'''),
    "sems_tag_file_sink": ("SemS Pilot Mapper → SemS OFDM Tx → SemS Target Channel (time domain) → **SemS Tag File Sink**", '''
import os
import tempfile
from gnuradio import analog, blocks, gr, sems
from gnuradio.sems.tag_file import read_tags, tag_file_sink

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
recording = os.path.join(tempfile.mkdtemp(), "rec")  # rec.sigmf-data and rec.sigmf-meta
tb = gr.top_block()
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
mapper = sems.pilot_mapper(pilot_positions=positions)
head = blocks.head(gr.sizeof_gr_complex * 64, 3 * 32)
channel = sems.target_channel_td(snr_db=20.0, seed=1)
recorder = tag_file_sink(recording, "complex", 1, sample_rate=30e6, frequency=3e9)  # keep a reference
tb.connect(data, mapper, head, sems.ofdm_tx(), channel, recorder)
tb.run()
print(recorder.count, "tags recorded with", os.path.getsize(recording + ".sigmf-data") // 8, "samples;",
      len(read_tags(recording)), "read back")
'''),
    "sems_tag_file_replay": ("File Source → **SemS Tag File Replay** → SemS OFDM Rx → SemS Pilot Extractor → Vector Sink", '''
import os
import tempfile
import pmt
from gnuradio import analog, blocks, gr, sems
from gnuradio.sems.tag_file import tag_file_replay, tag_file_sink

positions = [n * 64 + (5 * n) % 64 for n in range(32)]
recording = os.path.join(tempfile.mkdtemp(), "rec")
record = gr.top_block()  # a recording of 3 frames, as in SemS Tag File Sink's example
recorder = tag_file_sink(recording, "complex", 1, sample_rate=30e6)
data = analog.noise_source_c(analog.GR_GAUSSIAN, 1.0, 0)
head = blocks.head(gr.sizeof_gr_complex * 64, 3 * 32)
record.connect(data, sems.pilot_mapper(pilot_positions=positions), head, sems.ofdm_tx(),
               sems.target_channel_td(snr_db=20.0, seed=1), recorder)
record.run()

replay = gr.top_block()
source = blocks.file_source(gr.sizeof_gr_complex, recording + ".sigmf-data")
replayer = tag_file_replay(recording, "complex", 1)  # a Python block: keep a reference
sink = blocks.vector_sink_c(32)
replay.connect(source, replayer, sems.ofdm_rx(), sems.pilot_extractor(pilot_positions=positions), sink)
replay.run()
truths = [pmt.to_python(t.value) for t in sink.tags() if str(t.key) == sems.keys.truth_tag]
print(len(sink.data()) // 32, "frames replayed:", ", ".join(t["class_name"] for t in truths))
'''),
}


class Problems(list):
    def add(self, where, what):
        self.append(f"{where}: {what}")


# ---------------------------------------------------------------------------------------------
# Reading the sources

def grc_blocks(src):
    files = sorted(glob.glob(os.path.join(src, "grc", "sems_*.block.yml")))
    return [(os.path.relpath(f, src), yaml.safe_load(open(f, encoding="utf-8"))) for f in files]


def schema_problems(path, data):
    """GRC's own check of a block file: its messages (an ignored key is a warning there)."""
    try:
        from gnuradio.grc.core import schema_checker
    except ImportError:  # no GNU Radio Companion on this machine: nothing to check against
        return []
    checker = schema_checker.Validator(schema_checker.BLOCK_SCHEME)
    checker.run(data)
    return [f"{m.path}: {m.message}" for m in checker.messages]


def parse_documentation(text):
    """(prose paragraphs, {section: [its items] or the text of a one-line section})."""
    prose, sections, current = [], {}, None
    paragraph = []
    for line in text.split("\n"):
        head = re.match(r"^(%s):\s*(.*)$" % "|".join(SECTIONS), line)
        if head:
            current = head.group(1)
            sections[current] = head.group(2).strip() or []
            continue
        if current is None:
            if line.strip():
                paragraph.append(line.strip())
            elif paragraph:
                prose.append(" ".join(paragraph))
                paragraph = []
            continue
        if line.startswith("- "):
            if not isinstance(sections[current], list):
                sections[current] = []
            sections[current].append(line[2:].strip())
        elif line.strip() and line.startswith(" ") and isinstance(sections[current], list) and sections[current]:
            sections[current][-1] += " " + line.strip()
        elif line.strip():
            sections.setdefault("_stray", []).append(line.strip())
    if paragraph:
        prose.append(" ".join(paragraph))
    return prose, sections


def split_facts(text):
    """(description, unit, range) of a Parameters item: "Unit: x." and "Range: y." end it."""
    found = {}
    for key in ("Range", "Unit"):  # Range is the last sentence, Unit the one before
        m = re.search(r"(?:^|\s)%s: (.+?)\.?$" % key, text)
        if m:
            found[key] = m.group(1).strip()
            text = text[:m.start()].rstrip()
    return text, found.get("Unit"), found.get("Range")


def label_unit(label):
    """The unit a label states in parentheses ("Carrier (Hz)", "Taps (L, samples)"), or None."""
    for group in re.findall(r"\(([^)]*)\)", label):
        for part in group.split(","):
            words = part.split()
            if words and words[-1] in LABEL_UNITS:
                return words[-1]
    return None


SIMPLE_BOUND = re.compile(r"^(\w+)\s*(>=|<=|>|<)\s*(-?[\w.+]+)$")
OPS = {">=": "≥", "<=": "≤", ">": ">", "<": "<"}


def assert_bounds(asserts):
    """({parameter id: "≥ 1 and ≤ `n_subcarriers`"}, [the other asserts]) of a block's asserts."""
    bounds, other = {}, []
    for a in asserts or []:
        expr = re.sub(r"^\$\{\s*|\s*\}$", "", str(a).strip())
        parts = [SIMPLE_BOUND.match(p.strip()) for p in re.split(r"\s+and\s+", expr)]
        if all(parts) and len({p.group(1) for p in parts}) == 1:
            text = " and ".join(f"{OPS[p.group(2)]} {bound_value(p.group(3))}" for p in parts)
            pid = parts[0].group(1)
            bounds[pid] = bounds[pid] + " and " + text if pid in bounds else text
        else:
            other.append(expr)
    return bounds, other


def bound_value(v):
    return f"`{v}`" if re.match(r"^[A-Za-z_]", v) else v


def class_brief(src, name):
    """(header path, \\brief) of the C++ block class `name`, or None."""
    for d in HEADER_DIRS:
        for path in sorted(glob.glob(os.path.join(src, d, "*.h"))):
            text = open(path, encoding="utf-8").read()
            m = re.search(r"class SEMS_(?:LEARNING_)?API %s\b" % re.escape(name), text)
            if not m:
                continue
            block = text[text.rindex("/*!", 0, m.start()):m.start()]
            b = re.search(r"\\brief\s+(.*?)(?:\n\s*\*\s*\n|\\details|\\ingroup|\\param|\*/)", block, re.S)
            brief = " ".join(re.sub(r"\n\s*\*", " ", b.group(1)).split()) if b else ""
            return os.path.relpath(path, src), brief
    return None


def python_brief(src, module, name):
    """(file path, first paragraph of the class docstring) of the Python block `name`, or None."""
    candidates = [os.path.join(src, "python", "sems", module + ".py")] if module else \
        sorted(glob.glob(os.path.join(src, "python", "sems", "*.py")))
    for path in candidates:
        if not os.path.isfile(path):
            continue
        tree = ast.parse(open(path, encoding="utf-8").read())
        for node in tree.body:
            if isinstance(node, ast.ClassDef) and node.name == name:
                doc = ast.get_docstring(node) or ""
                return os.path.relpath(path, src), " ".join(doc.split("\n\n")[0].split())
    return None


def tag_keys(src):
    """{stream-tag key: what it carries} from tags.h (the constants named *_tag)."""
    text = open(os.path.join(src, TAGS_H), encoding="utf-8").read()
    return {m.group(1): m.group(2).strip() for m in
            re.finditer(r'constexpr const char\* \w+_tag = "(\w+)"; ///< (.*)', text)}


def design_anchors(src):
    """{"§N": anchor} of docs/design.md's numbered sections."""
    out = {}
    for line in open(os.path.join(src, "docs", "design.md"), encoding="utf-8"):
        m = re.match(r"^## (\d+)\. (.*)$", line.strip())
        if m:
            slug = re.sub(r"[^\w\- ]", "", f"{m.group(1)}. {m.group(2)}".lower()).replace(" ", "-")
            out["§" + m.group(1)] = slug
    return out


def shipped_examples(src, block_id):
    found = []
    for path in sorted(glob.glob(os.path.join(src, "examples", "*.grc"))):
        if re.search(r"^\s*(?:-\s+)?id: %s\s*$" % re.escape(block_id), open(path, encoding="utf-8").read(), re.M):
            found.append(os.path.relpath(path, src))
    return found


# ---------------------------------------------------------------------------------------------
# Markdown

def md_text(text, src, anchors, cell=False):
    """Escapes text for Markdown outside its `code` spans, and links the docs pages it names."""
    out = []
    for i, part in enumerate(re.split(r"(`[^`]*`)", text)):
        if i % 2:
            out.append(part)
            continue
        part = part.replace("\\", "\\\\").replace("*", "\\*").replace("<", "\\<")
        if cell:
            part = part.replace("|", "\\|")

        def link(m):
            path = m.group(1)
            section = m.group(2)
            target = os.path.relpath(os.path.join(src, path), os.path.join(src, OUT))
            if section and path == "docs/design.md" and section.strip() in anchors:
                target += "#" + anchors[section.strip()]
            return f"[{m.group(0)}]({target})"
        part = re.sub(r"((?:docs|models|examples)/[\w/.\\-]*?\.md)( §\d+)?", link, part)
        out.append(part)
    return "".join(out)


def show_default(p):
    d = p.get("default")
    if p.get("dtype") == "enum":
        opts, labels = [str(o) for o in p.get("options", [])], [str(x) for x in p.get("option_labels", [])]
        if str(d) in opts and labels:
            return f"{labels[opts.index(str(d))]} (`{d}`)"
        return f"`{d}`"
    if d is None or str(d) in ("", "''", '""'):
        return "empty"
    return f"`{d}`"


def show_options(p):
    opts = [str(o) for o in p.get("options", [])]
    if "option_labels" not in p:
        return ", ".join(f"`{o}`" for o in opts)
    return ", ".join(f"{label} (`{o}`)" for o, label in zip(opts, [str(x) for x in p["option_labels"]]))


def visibility(p):
    """The condition under which GRC shows a parameter, from its hide expression, or None."""
    hide = str(p.get("hide", ""))
    m = re.match(r"^\$\{\s*\(\s*'(?:none|part)' if (.+) else 'all'\s*\)\s*\}$", hide)
    return m.group(1).strip() if m else None


def port_name(port):
    return str(port.get("label") or port.get("id") or "")


def show_vlen(port):
    v = str(port.get("vlen", 1))
    v = re.sub(r"^\$\{\s*|\s*\}$", "", v)
    return v if v == "1" else f"`{v}`"


def show_item(port):
    t = str(port.get("dtype", ""))
    m = re.match(r"^\$\{\s*(\w+)\s*\}$", t)
    return f"the Item type (`{m.group(1)}`)" if m else ITEM_TYPES.get(t, t)


# ---------------------------------------------------------------------------------------------
# The pages

def block_page(src, path, d, keys, anchors, problems):
    """(Markdown of a block's page, its index row) for the block file `path` with data d."""
    bid, label = d["id"], d["label"]
    where = path
    prose, sections = parse_documentation(str(d.get("documentation", "")))
    for stray in sections.get("_stray", []):
        problems.add(where, f"documentation: '{stray[:60]}' is outside any list item")

    # The block's implementation: C++ class (its header's \brief) or Python class (docstring).
    templates = d.get("templates", {})
    make = str(templates.get("make", ""))
    imports = str(templates.get("imports", ""))
    m = re.match(r"^\s*(?:sems\.)?(\w+)\(", make)
    cls = m.group(1) if m else None
    module = re.search(r"from gnuradio\.sems\.(\w+) import %s\b" % re.escape(cls or "-"), imports)
    impl = class_brief(src, cls) if cls and not module else None
    py = None if impl else (python_brief(src, module.group(1) if module else None, cls) if cls else None)
    if impl:
        impl_path, purpose = impl
        api = (f"Python `sems.{cls}(...)`; C++ `gr::sems::{cls}::make(...)` in "
               f"[`{impl_path}`]({os.path.relpath(os.path.join(src, impl_path), os.path.join(src, OUT))})")
    elif py:
        impl_path, purpose = py
        mod = module.group(1) if module else None
        call = f"gnuradio.sems.{mod}.{cls}" if mod else f"sems.{cls}"
        api = f"Python `{call}(...)` in [`{impl_path}`]({os.path.relpath(os.path.join(src, impl_path), os.path.join(src, OUT))})"
    else:
        problems.add(where, f"templates.make names no class of the headers or of python/sems ({cls!r})")
        purpose, api = "", ""
    if not purpose:
        problems.add(where, f"{cls}: no \\brief or docstring to state the block's purpose")

    lines = [f"<!-- {MARK} -->",
             f"<!-- Generated by scripts/block_reference.py from {path}"
             + (f" and {impl_path}" if impl or py else "") + ": edit those, then run it with --write. -->",
             f"# {label}", "",
             md_text(purpose, src, anchors), "",
             f"GRC block `{bid}` in [`{path}`](../../../{path}), category *{str(d.get('category', '')).strip('[]')}*; "
             + api + ".", ""]

    # Ports.
    port_items = {}
    for item in sections.get("Ports", []) if isinstance(sections.get("Ports"), list) else []:
        name, _, text = item.partition(":")
        port_items[name.strip()] = text.strip()
    if not isinstance(sections.get("Ports"), list) and (d.get("inputs") or d.get("outputs")):
        problems.add(where, "documentation: no Ports list")
    stream, message, named = [], [], set()
    for direction, key in (("in", "inputs"), ("out", "outputs")):
        for port in d.get(key, []) or []:
            name = port_name(port)
            if name in named:
                problems.add(where, f"two ports named {name!r}: a Ports item could not tell them apart")
            named.add(name)
            text = port_items.get(name)
            if text is None:
                problems.add(where, f"port {direction} {name!r}: no Ports item ('- {name}: <rate>; <what>')")
                rate, what = "", ""
            else:
                rate, _, what = text.partition(";")
                rate, what = rate.strip(), what.strip()
                if not re.search(r"\b(per|every)\b", rate):
                    problems.add(where, f"port {name!r}: the rate '{rate}' says neither 'per' nor 'every'")
            optional = " (optional)" if str(port.get("optional", "")).lower() in ("true", "1") else ""
            if port.get("domain") == "message":
                message.append(f"| {direction} | `{name}`{optional} | {md_text(rate, src, anchors, True)} | "
                               f"{md_text(what, src, anchors, True)} |")
            else:
                stream.append(f"| {direction} | {name}{optional} | {show_item(port)} | {show_vlen(port)} | "
                              f"{md_text(rate, src, anchors, True)} | {md_text(what, src, anchors, True)} |")
    for name in port_items:
        if name not in named:
            problems.add(where, f"Ports item {name!r} names no port of the block")
    lines += ["## Ports", ""]
    if stream:
        lines += ["| | port | item | vector length | rate | carries |", "|---|---|---|---|---|---|"] + stream + [""]
    if message:
        lines += ["Message ports:", "", "| | port | rate | carries |", "|---|---|---|---|"] + message + [""]
    if not stream and not message:
        lines += ["None.", ""]

    # Parameters.
    params = d.get("parameters", []) or []
    by_label = {str(p["label"]): p for p in params}
    items = {}
    for item in sections.get("Parameters", []) if isinstance(sections.get("Parameters"), list) else []:
        match = [lb for lb in by_label if item.startswith(lb + ": ")]
        if not match:
            problems.add(where, f"Parameters item '{item[:50]}' names no parameter label of the block")
            continue
        lb = max(match, key=len)
        items[lb] = item[len(lb) + 2:].strip()
    bounds, other_asserts = assert_bounds(d.get("asserts"))
    table, descriptions = [], []
    for p in params:
        pid, lb, dtype = p["id"], str(p["label"]), str(p.get("dtype", ""))
        text = items.get(lb)
        if text is None:
            problems.add(where, f"parameter {pid} ({lb}): no Parameters item ('- {lb}: ...')")
            text = ""
        desc, unit, rng = split_facts(text)
        if "default" not in p:
            problems.add(where, f"parameter {pid}: no default")
        lunit = label_unit(lb)
        if dtype in NUMERIC:
            if lunit and unit:
                problems.add(where, f"parameter {pid}: unit stated twice (label '{lb}' and 'Unit: {unit}')")
            if not lunit and not unit:
                problems.add(where, f"parameter {pid} ({lb}): no unit (label in parentheses, or 'Unit: ...', "
                                    "'Unit: none.' for a pure number)")
            if pid in bounds and rng:
                problems.add(where, f"parameter {pid}: range stated twice (assert '{bounds[pid]}' and 'Range: {rng}')")
            if pid not in bounds and not rng:
                problems.add(where, f"parameter {pid} ({lb}): no range (an assert bounding it, or 'Range: ...')")
        elif unit:
            problems.add(where, f"parameter {pid}: a {dtype} has no unit ('Unit: {unit}')")
        show_unit = unit or lunit or "—"
        if show_unit == "none":
            show_unit = "—"
        if dtype == "enum":
            show_range = show_options(p)
        elif dtype == "bool":
            show_range = "`True`, `False`"
        else:
            show_range = md_text(rng.replace(">=", "≥").replace("<=", "≤"), src, anchors, True) if rng \
                else (bounds.get(pid) or "—")
        table.append(f"| {md_text(lb, src, anchors, True)} | `{pid}` | {dtype} | {md_text(show_unit, src, anchors, True)} "
                     f"| {show_default(p)} | {show_range} |")
        when = visibility(p)
        descriptions.append(f"- **{md_text(lb, src, anchors)}**: {md_text(desc, src, anchors)}"
                            + (f" Shown when `{when}`." if when else ""))
    lines += ["## Parameters", ""]
    if params:
        lines += ["| label | id | type | unit | default | range |", "|---|---|---|---|---|---|"] + table + [""]
        lines += descriptions + [""]
        if other_asserts:
            lines += ["GRC also checks " + "; ".join(f"`{a}`" for a in other_asserts) + ".", ""]
    else:
        lines += ["None.", ""]

    # Tags.
    lines += ["## Stream tags", ""]
    tags = sections.get("Tags")
    if isinstance(tags, str) and tags:
        lines += [md_text(tags[:1].upper() + tags[1:], src, anchors), ""]
    elif isinstance(tags, list) and tags:
        rows = []
        for item in tags:
            m = re.match(r"^(reads|writes|passes) ([^:]+): (.*)$", item)
            if not m:
                problems.add(where, f"Tags item '{item[:50]}': expected 'reads|writes|passes <key>: <how>'")
                continue
            verb, key, how = m.group(1), m.group(2).strip(), m.group(3).strip()
            if key in keys:
                carries = md_text(keys[key], src, anchors, True) + \
                    f" ([design §3](../../design.md#{anchors.get('§3', '')}))"
                shown = f"`{key}`"
            elif key.startswith(("every tag", "other tags")):
                carries, shown = "—", md_text(key, src, anchors, True)
            else:
                problems.add(where, f"Tags item: {key!r} is not a stream-tag key of {TAGS_H}")
                continue
            rows.append(f"| {verb} | {shown} | {carries} | {md_text(how, src, anchors, True)} |")
        lines += ["| | key | carries | here |", "|---|---|---|---|"] + rows + [""]
    else:
        problems.add(where, "documentation: no Tags list (or 'Tags: none (<why>).')")

    # Details: the documentation's prose.
    # A paragraph that only restates the purpose is left out.
    prose = [para for para in prose if not " ".join(purpose.split()).startswith(para.rstrip("."))]
    if prose:
        lines += ["## Details", ""]
        for para in prose:
            lines += [md_text(para, src, anchors), ""]

    # Example.
    lines += ["## Example", ""]
    if bid in EXAMPLES:
        chain, code = EXAMPLES[bid]
        lines += [chain, "", "```python", code.strip("\n"), "```", ""]
    else:
        problems.add(where, "no example in EXAMPLES of scripts/block_reference.py")
    shipped = shipped_examples(src, bid)
    if shipped:
        lines += ["Shipped flowgraphs with this block: "
                  + ", ".join(f"[`{os.path.basename(s)}`](../../../{s})" for s in shipped)
                  + " ([examples](../../../examples/README.md)).", ""]
    lines += ["[All SemS blocks](README.md)", "", f"<!-- /{MARK} -->"]

    ins = ", ".join(port_name(p) for p in d.get("inputs", []) or []) or "—"
    outs = ", ".join(port_name(p) for p in d.get("outputs", []) or []) or "—"
    row = f"| [{label}]({bid}.md) | `{bid}` | {ins} | {outs} | {md_text(purpose, src, anchors, True)} |"
    return "\n".join(lines) + "\n", row


def index_page(rows):
    return "\n".join([
        f"<!-- {MARK} -->",
        "<!-- Generated by scripts/block_reference.py: edit the block files and headers, then run it with --write. -->",
        "# Block reference", "",
        "One page per block of GNU Radio Companion's *SemS* category: what it does, its ports with "
        "their item type, vector length and rate, every parameter with its unit, default and range, "
        "the stream tags it reads and writes, and a minimal flowgraph with its Python.", "",
        "| block | id | inputs | outputs | purpose |", "|---|---|---|---|---|"] + rows + [
        "",
        "The pages are generated from the block files (`grc/`), the headers' Doxygen and the Python "
        "blocks' docstrings; this command writes them (CTest `block_reference` runs it with --check: the pages "
        "must match, and every example runs):", "",
        "    /usr/bin/python3 scripts/block_reference.py . --write", "",
        f"<!-- /{MARK} -->"]) + "\n"


def generate(src, problems):
    """{relative path: text} of every page."""
    keys, anchors = tag_keys(src), design_anchors(src)
    blocks = grc_blocks(src)
    if not blocks:
        problems.add("grc", "no sems_*.block.yml")
    by_id = {}
    for path, d in blocks:
        for msg in schema_problems(path, d):
            problems.add(path, f"GRC's schema check: {msg}")
        by_id[d["id"]] = (path, d)
    pages, rows = {}, []
    order = [b for b in EXAMPLES if b in by_id] + sorted(b for b in by_id if b not in EXAMPLES)
    for b in EXAMPLES:
        if b not in by_id:
            problems.add("scripts/block_reference.py", f"EXAMPLES has {b}, which is no block of grc/")
    for bid in order:
        path, d = by_id[bid]
        page, row = block_page(src, path, d, keys, anchors, problems)
        pages[os.path.join(OUT, bid + ".md")] = page
        rows.append(row)
    pages[os.path.join(OUT, "README.md")] = index_page(rows)
    for rel, text in pages.items():
        if text.count("\n") > 400:
            problems.add(rel, f"{text.count(chr(10))} lines, more than 400")
    check_readme(src, by_id, problems)
    return pages


def check_readme(src, by_id, problems):
    """README.md's block table links every block's row to its page."""
    text = open(os.path.join(src, "README.md"), encoding="utf-8").read()
    m = re.search(r"^## The blocks\n(.*?)(?=^## )", text, re.M | re.S)
    table = m.group(1) if m else ""
    for bid, (_, d) in sorted(by_id.items()):
        if not re.search(r"^\| \[[^\]]+\]\(%s\) \|" % re.escape(f"{OUT}/{bid}.md"), table, re.M):
            problems.add("README.md", f"'## The blocks': no row of {d['label']} linking its page {OUT}/{bid}.md")


# ---------------------------------------------------------------------------------------------
# Running the examples

RUNNER = r'''
import sys, time, traceback
failed = 0
for name, code in SNIPPETS:
    t0 = time.time()
    print("== %s" % name, flush=True)
    try:
        exec(compile(code, name, "exec"), {"__name__": "__main__"})
    except Exception:
        traceback.print_exc()
        failed += 1
    print("   %.2f s" % (time.time() - t0), flush=True)
sys.exit(1 if failed else 0)
'''


def run_examples(pages, problems):
    """Runs the Python block of every page in one interpreter (they share its imports)."""
    snippets = []
    for rel, text in sorted(pages.items()):
        for code in re.findall(r"^```python\n(.*?)^```", text, re.M | re.S):
            snippets.append((rel, code))
    if not snippets:
        problems.add(OUT, "no example found in the pages")
        return
    program = "SNIPPETS = %r\n%s" % (snippets, RUNNER)
    with tempfile.TemporaryDirectory() as work:  # the examples' files (TMPDIR) go with it
        env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"), TMPDIR=work)
        try:
            r = subprocess.run([sys.executable, "-c", program], cwd=work, env=env,
                               capture_output=True, text=True, timeout=300)
        except subprocess.TimeoutExpired as e:
            out = e.stdout or b""
            print(out.decode(errors="replace") if isinstance(out, bytes) else out, end="")
            problems.add(OUT, "the examples did not finish in 300 s")
            return
    print(r.stdout, end="")
    if r.returncode != 0:
        print(r.stderr, end="", file=sys.stderr)
        # A traceback names its page; a crash (no traceback) happened in the last one begun.
        failed = sorted(set(re.findall(r'File "(%s/[^"]+)"' % re.escape(OUT), r.stderr)))
        begun = re.findall(r"^== (.+)$", r.stdout, re.M)
        for page in failed or begun[-1:] or [OUT]:
            problems.add(page, f"its example failed (exit status {r.returncode})")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", help="the repository's root")
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", action="store_true", help="write the pages into docs/reference/blocks/")
    mode.add_argument("--check", action="store_true", help="compare the pages with the generated ones, run the examples")
    ap.add_argument("--no-run", action="store_true", help="with --check: do not run the examples")
    a = ap.parse_args()
    src = os.path.abspath(a.source)
    problems = Problems()
    pages = generate(src, problems)
    if a.write:
        out = os.path.join(src, OUT)
        os.makedirs(out, exist_ok=True)
        for rel, text in pages.items():
            with open(os.path.join(src, rel), "w", encoding="utf-8") as f:
                f.write(text)
        for old in glob.glob(os.path.join(out, "*.md")):
            if os.path.relpath(old, src) not in pages:
                os.remove(old)
        print(f"block_reference: wrote {len(pages)} pages into {OUT}")
    else:
        with tempfile.TemporaryDirectory() as tmp:  # the generated pages, as --write would write them
            for rel, text in pages.items():
                os.makedirs(os.path.dirname(os.path.join(tmp, rel)), exist_ok=True)
                with open(os.path.join(tmp, rel), "w", encoding="utf-8") as f:
                    f.write(text)
            committed = {os.path.relpath(p, src) for p in glob.glob(os.path.join(src, OUT, "*.md"))}
            for rel in sorted(set(pages) | committed):
                new = os.path.join(tmp, rel)
                old = os.path.join(src, rel)
                if not os.path.exists(old):
                    problems.add(rel, "missing: run scripts/block_reference.py --write")
                elif not os.path.exists(new):
                    problems.add(rel, "no block has this page: run scripts/block_reference.py --write")
                else:
                    a_text, b_text = open(old, encoding="utf-8").read(), open(new, encoding="utf-8").read()
                    if a_text != b_text:
                        diff = list(difflib.unified_diff(a_text.splitlines(), b_text.splitlines(), rel, "generated",
                                                         lineterm="", n=0))
                        problems.add(rel, "differs from the generated page (run scripts/block_reference.py "
                                          "--write):\n  " + "\n  ".join(diff[2:12]))
        if not a.no_run:
            run_examples(pages, problems)
    for p in problems:
        print(p)
    print(f"block_reference: {len(pages) - 1} blocks, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
