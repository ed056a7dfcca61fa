# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: keep a stream's tags across a raw recording (file_sink drops them).

tag_file_sink writes every tag of its input stream to a sidecar, one JSON line per tag:
{"offset": item index from the start of the stream, "key": tag key,
 "value": base64 of pmt.serialize_str(value)} (bit-exact PMTs: sems_truth dicts,
sems_frame indices). tag_file_replay passes a stream through and puts the sidecar's tags
back on the same item offsets, so a replay from file_source carries the recorded truth.
"""
import base64
import json

import numpy as np
import pmt
from gnuradio import gr


def _signature(who, item, vlen):
    """The io signature entry; validated before the gateway is made (a Python block that
    raises after gr.sync_block.__init__ can crash the interpreter at teardown)."""
    if item not in ("complex", "float"):
        raise ValueError(f"{who}: item must be 'complex' or 'float', got {item!r}")
    if vlen < 1:
        raise ValueError(f"{who}: vlen must be >= 1, got {vlen}")
    dt = np.complex64 if item == "complex" else np.float32
    return dt if vlen == 1 else (dt, vlen)


class tag_file_sink(gr.sync_block):
    """Writes the tags of its input to `path` (JSON lines); the items are discarded."""

    def __init__(self, path, item="complex", vlen=1):
        if not path:
            raise ValueError("tag_file_sink: path is empty")
        sig = _signature("tag_file_sink", item, vlen)
        try:
            f = open(path, "w")
        except OSError as e:
            raise ValueError(f"tag_file_sink: cannot write {path}: {e}") from None
        gr.sync_block.__init__(self, "tag_file_sink", in_sig=[sig], out_sig=None)
        self.path = path
        self.count = 0
        self._file = f

    def work(self, input_items, output_items):
        n = len(input_items[0])
        start = self.nitems_read(0)
        for t in self.get_tags_in_range(0, start, start + n):
            value = base64.b64encode(pmt.serialize_str(t.value)).decode("ascii")
            self._file.write(json.dumps({"offset": t.offset, "key": pmt.symbol_to_string(t.key),
                                         "value": value}) + "\n")
            self.count += 1
        return n

    def stop(self):
        self._file.close()
        return True


def read_tags(path):
    """The sidecar's tags as (offset, key, pmt value), in file order. Raises ValueError
    naming the file and line on a malformed line."""
    tags = []
    try:
        with open(path) as f:
            for line_no, line in enumerate(f, 1):
                try:
                    d = json.loads(line)
                    tags.append((int(d["offset"]), str(d["key"]),
                                 pmt.deserialize_str(base64.b64decode(d["value"]))))
                except (ValueError, KeyError, TypeError) as e:
                    raise ValueError(f"{path}:{line_no}: not a tag line: {e}") from None
    except OSError as e:
        raise ValueError(f"tag_file_replay: cannot read {path}: {e}") from None
    return tags


class tag_file_replay(gr.sync_block):
    """Passes its input through and adds the sidecar's tags at their recorded offsets."""

    def __init__(self, path, item="complex", vlen=1):
        sig = _signature("tag_file_replay", item, vlen)
        tags = sorted(read_tags(path), key=lambda t: t[0])
        gr.sync_block.__init__(self, "tag_file_replay", in_sig=[sig], out_sig=[sig])
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
