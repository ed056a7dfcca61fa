# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: record a stream with its tags (File Sink drops them) and put them back on replay.

tag_file_sink records its input as the SigMF recording PATH: the samples in PATH.sigmf-data
(raw little-endian, as File Sink writes them) and PATH.sigmf-meta with one annotation per
frame holding the frame's truth and every tag bit-exactly (gnuradio.sems.sigmf describes the
fields). tag_file_replay, right after a File Source reading PATH.sigmf-data, passes the
stream through and puts the tags back on the same item offsets, so a replay carries the
recorded frame starts and truth.

A PATH ending in .tags is the JSON-lines tag file of earlier versions, one line per tag
{"offset", "key", "value": base64 of pmt.serialize_str}: the sink writes only the tags (the
samples go to a File Sink of their own), the replay reads such a file. `python3 -m
gnuradio.sems.sigmf convert` turns such a recording into SigMF.
"""
import base64
import json

import numpy as np
import pmt
from gnuradio import gr

from . import sigmf
from .sigmf import read_tags  # noqa: F401  (the tags of either kind of recording)


def _signature(who, item, vlen):
    """The io signature entry; validated before the gateway is made (a Python block that
    raises after gr.sync_block.__init__ can crash the interpreter at teardown)."""
    if item not in sigmf.DATATYPES:
        raise ValueError(f"{who}: item must be 'complex' or 'float', got {item!r}")
    if vlen < 1:
        raise ValueError(f"{who}: vlen must be >= 1, got {vlen}")
    dt = np.complex64 if item == "complex" else np.float32
    return dt if vlen == 1 else (dt, vlen)


class tag_file_sink(gr.sync_block):
    """Records its input with every tag as the SigMF recording `path` (path.sigmf-data and
    path.sigmf-meta; a path ending in .sigmf-meta or .sigmf-data names the same pair).

    sample_rate (S/s) and frequency (the centre frequency, Hz) go into the metadata; 0 leaves
    them out. frame_len: items per frame, for the frames' annotations; 0 takes each frame's
    length from the tags (a frame ends at the next sems_frame tag, the last one at the end of
    the recording). description: core:description (empty: a sentence on what the annotations
    hold). The metadata is complete when the flowgraph stops.

    A path ending in .tags writes only the tags, one JSON line each, as earlier versions did;
    the items are discarded and the other settings unused."""

    def __init__(self, path, item="complex", vlen=1, sample_rate=0.0, frequency=0.0, frame_len=0,
                 description=""):
        if not path:
            raise ValueError("tag_file_sink: path is empty")
        sig = _signature("tag_file_sink", item, vlen)
        vlen, sample_rate, frequency, frame_len = sigmf.check_settings(
            "tag_file_sink", item, vlen, sample_rate, frequency, frame_len)
        self._lines = self._data = self._meta = None
        target = path  # the file being opened, for the error
        try:
            if sigmf.is_tag_lines(path):
                self._lines = open(path, "w")
            else:
                meta_path, target = sigmf.recording_paths(path)
                self._data = open(target, "wb")
                target = meta_path
                self._meta = sigmf.meta_writer(meta_path, item, vlen, sample_rate, frequency, frame_len,
                                               description, recorder="gr-sems tag_file_sink, GNU Radio "
                                               + gr.version())
        except OSError as e:
            raise ValueError(f"tag_file_sink: cannot write {target}: {e.strerror}") from None
        gr.sync_block.__init__(self, "tag_file_sink", in_sig=[sig], out_sig=None)
        self.path = path
        self.count = 0  # tags recorded
        self._dtype = sigmf.item_dtype(item)  # of one value: x has shape (n,) or (n, vlen)
        self._begun = False

    @property
    def annotations(self):
        """The annotations written to the metadata so far (frames, and groups of tags outside
        every frame; 0 for a .tags file)."""
        return self._meta.annotations if self._meta is not None else 0

    def start(self):
        if self._meta is not None and not self._begun:
            self._meta.begin(sigmf.utc_now())  # the time of (about) the first sample
            self._begun = True
        return True

    def work(self, input_items, output_items):
        x = input_items[0]
        n = len(x)
        if self._data is not None:
            # SigMF data is little-endian: a no-op on little-endian hosts, a swap on others.
            self._data.write(np.ascontiguousarray(x, dtype=self._dtype).data)
        start = self.nitems_read(0)
        for t in sorted(self.get_tags_in_range(0, start, start + n), key=lambda t: t.offset):
            key, blob = pmt.symbol_to_string(t.key), pmt.serialize_str(t.value)
            if self._lines is not None:
                self._lines.write(json.dumps({"offset": t.offset, "key": key,
                                              "value": base64.b64encode(blob).decode("ascii")}) + "\n")
            else:
                self._meta.add(t.offset, key, t.value, blob)
            self.count += 1
        return n

    def stop(self):
        if self._lines is not None:
            self._lines.close()
        if self._data is not None:
            self._data.close()
            if not self._begun:  # never started: still a valid (empty) recording
                self._meta.begin(None)
                self._begun = True
            self._meta.finish(self.nitems_read(0))
        return True


class tag_file_replay(gr.sync_block):
    """Passes its input through and adds a recording's tags at their recorded item offsets.

    path: the SigMF recording (NAME, NAME.sigmf-meta or NAME.sigmf-data) whose data file the
    File Source before this block reads, or a JSON-lines tag file (a name ending in .tags).
    A SigMF recording is checked first: its metadata against the specification's required
    fields, its datatype against `item` (cf32_le for complex, rf32_le for float) and
    core:num_channels against `vlen`, its data file for existing and holding whole items;
    errors name the file. A SigMF recording from another tool (no sems:tags) replays without
    tags."""

    def __init__(self, path, item="complex", vlen=1):
        if not path:
            raise ValueError("tag_file_replay: path is empty")
        sig = _signature("tag_file_replay", item, vlen)
        tags = read_tags(path, item, vlen)
        gr.sync_block.__init__(self, "tag_file_replay", in_sig=[sig], out_sig=[sig])
        self.path = path
        self.tags = tags
        self._next = 0
        self.set_tag_propagation_policy(gr.TPP_DONT)
        self._srcid = pmt.intern("tag_file_replay")

    def work(self, input_items, output_items):
        n = len(input_items[0])
        output_items[0][:n] = input_items[0][:n]
        end = self.nitems_written(0) + n
        while self._next < len(self.tags) and self.tags[self._next][0] < end:
            offset, key, value = self.tags[self._next]
            self.add_item_tag(0, offset, pmt.intern(key), value, self._srcid)
            self._next += 1
        return n
