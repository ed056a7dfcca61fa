# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: recordings in SigMF, the Signal Metadata Format (github.com/sigmf/SigMF; the
version of its specification followed is SPEC_VERSION), with every stream tag kept bit-exactly.

A recording NAME is two files: NAME.sigmf-data, the raw little-endian samples (cf32_le for
complex items, rf32_le for float; what GNU Radio's File Sink writes), and NAME.sigmf-meta,
JSON: the global object (datatype, sample rate, recorder, the `sems` extension), one capture
(centre frequency, UTC time of the first sample) and one annotation per frame. A frame starts
at a `sems_frame` tag and runs to the next one (or frame_len items); its annotation holds
the frame's truth (the `sems_truth` dict's fields as `sems:` fields) and `sems:tags`, every
tag on the frame's items as {"offset", "key", "value": base64 of pmt.serialize_str}. Tags
outside every frame get a one-item annotation per item they are on. The `sems` extension is
defined in docs/reference/sems.sigmf-ext.md.

Also reads the JSON-lines tag files of earlier versions of tag_file_sink (NAME.tags, one line
per tag: {"offset", "key", "value"}), converts such a recording to SigMF, and checks a
metadata file against the specification's rules:

    /usr/bin/python3 -m gnuradio.sems.sigmf convert OLD.c64 [--tags OLD.c64.tags] [--out NAME] ...
    /usr/bin/python3 -m gnuradio.sems.sigmf check NAME.sigmf-meta
"""
import argparse
import base64
import binascii
import calendar
import datetime
import json
import keyword
import math
import numbers
import os
import re
import shutil
import sys

import numpy as np
import pmt

from .core_python import keys

SPEC_VERSION = "1.2.5"  # the SigMF specification these files follow (github.com/sigmf/SigMF)
EXTENSION = {"name": "sems", "version": "1.0.0", "optional": True}
META, DATA = ".sigmf-meta", ".sigmf-data"
TAG_LINES = ".tags"  # the JSON-lines tag files of earlier versions

FRAME_TAG, TRUTH_TAG = keys.frame_tag, keys.truth_tag  # core/common/tags.h
DATATYPES = {"complex": "cf32_le", "float": "rf32_le"}
_DTYPES = {"cf32_le": np.dtype("<c8"), "rf32_le": np.dtype("<f4")}

# The truth dict's keys become `sems:` field names; the specification forbids C++ and Python
# keywords as names, so `class` takes the name C++ gives its key (keys::class_id).
_FIELD_NAMES = {keys.class_id: "class_id"}
_RESERVED = {"tags"}  # sems:tags holds the tags themselves

_CXX20_KEYWORDS = set("""alignas alignof and and_eq asm auto bitand bitor bool break case catch char
    char8_t char16_t char32_t class compl concept const consteval constexpr constinit const_cast
    continue co_await co_return co_yield decltype default delete do double dynamic_cast else enum
    explicit export extern false float for friend goto if inline int long mutable namespace new
    noexcept not not_eq nullptr operator or or_eq private protected public register
    reinterpret_cast requires return short signed sizeof static static_assert static_cast struct
    switch template this thread_local throw true try typedef typeid typename union unsigned using
    virtual void volatile wchar_t while xor xor_eq""".split())
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_DATATYPE = re.compile(r"[cr](?:(?:f32|f64|i32|i16|u32|u16)_(?:le|be)|i8|u8)\Z")  # the spec's ABNF
_VERSION = re.compile(r"\d+\.\d+\.\d+\Z")
_DATETIME = re.compile(r"(\d{4})-(\d{2})-(\d{2})T(\d{2}):(\d{2}):(\d{2})(\.\d+)?Z\Z")  # RFC 3339, UTC only
_INDEX_MAX = 2**63 - 1
_FREQ_MAX = 1e12

# The core fields of each object and their JSON types (the specification's schema).
_INT, _NUM, _STR, _BOOL, _OBJ, _LIST = "integer", "number", "string", "boolean", "object", "array"
_CORE = {
    "global": {"datatype": _STR, "sample_rate": _NUM, "author": _STR, "collection": _STR,
               "dataset": _STR, "data_doi": _STR, "description": _STR, "hw": _STR, "license": _STR,
               "metadata_only": _BOOL, "meta_doi": _STR, "num_channels": _INT, "offset": _INT,
               "recorder": _STR, "sha512": _STR, "trailing_bytes": _INT, "version": _STR,
               "geolocation": _OBJ, "extensions": _LIST},
    "captures": {"sample_start": _INT, "datetime": _STR, "frequency": _NUM, "global_index": _INT,
                 "header_bytes": _INT, "geolocation": _OBJ},
    "annotations": {"sample_start": _INT, "sample_count": _INT, "freq_lower_edge": _NUM,
                    "freq_upper_edge": _NUM, "label": _STR, "comment": _STR, "generator": _STR,
                    "uuid": _STR},
}


def recording_paths(path):
    """(NAME.sigmf-meta, NAME.sigmf-data) of the recording named by NAME or either file."""
    for suffix in (META, DATA):
        if path.endswith(suffix):
            path = path[:-len(suffix)]
    return path + META, path + DATA


def is_tag_lines(path):
    """True for a JSON-lines tag file of earlier versions (its name ends in .tags)."""
    return path.endswith(TAG_LINES)


def item_dtype(item, vlen=1):
    """The numpy dtype of one stream item as stored on disk (little-endian)."""
    dt = _DTYPES[DATATYPES[item]]
    return dt if vlen == 1 else np.dtype((dt, vlen))


def utc_now():
    """The current time as SigMF's core:datetime (RFC 3339, UTC, microseconds)."""
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%S.%fZ")


def _is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def _is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _json_value(v):
    """A truth value as JSON: numbers, strings, null (also for inf and NaN), arrays, objects."""
    if v is None or isinstance(v, (bool, str)):
        return v
    if isinstance(v, np.bool_):
        return bool(v)
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        f = float(v)
        return f if math.isfinite(f) else None
    if isinstance(v, numbers.Complex):
        return [_json_value(v.real), _json_value(v.imag)]
    if isinstance(v, dict):
        return {str(k): _json_value(x) for k, x in v.items()}
    if isinstance(v, np.ndarray):
        return [_json_value(x) for x in v.tolist()]
    if isinstance(v, (list, tuple)):
        return [_json_value(x) for x in v]
    return str(v)


def _valid_name(name):
    return bool(_NAME.match(name)) and not keyword.iskeyword(name) and name not in _CXX20_KEYWORDS


def truth_fields(value):
    """The `sems:` fields of a sems_truth PMT dict: each key (class as class_id) with its value
    as JSON (inf and NaN as null). Keys that are no valid field name are left out; the tag's
    bit-exact copy in sems:tags keeps them."""
    if not pmt.is_dict(value):
        return {}
    try:
        d = pmt.to_python(value)
    except Exception:  # a PMT type pmt.to_python does not know
        return {}
    fields = {}
    for k, v in sorted(d.items(), key=lambda kv: str(kv[0])):
        name = _FIELD_NAMES.get(str(k), str(k))
        if _valid_name(name) and name not in _RESERVED:
            fields["sems:" + name] = _json_value(v)
    return fields


class meta_writer:
    """Writes NAME.sigmf-meta as a stream is recorded: the global object and the capture at
    begin(), each annotation as soon as its frame is complete (add() gets the tags in offset
    order), the rest at finish(n_items). Memory does not grow with the recording.

    Frames: a frame starts at every offset that carries a sems_frame tag. With frame_len 0 it
    ends where the next one starts (the last one at the end of the recording); with frame_len
    > 0 it is frame_len items long (the last one cut at the end of the recording)."""

    def __init__(self, path, item="complex", vlen=1, sample_rate=0.0, frequency=0.0, frame_len=0,
                 description="", recorder="gr-sems"):
        self.path = path
        self.item, self.vlen, self.frame_len = item, vlen, frame_len
        self.sample_rate, self.frequency = sample_rate, frequency
        self.description, self.recorder = description, recorder
        self.annotations = 0
        self._file = open(path, "w", encoding="utf-8")  # OSError: the caller names the file
        self._frame = None  # [start, [(offset, key, value, blob)]]
        self._at, self._group = None, []  # the tags at the offset being read
        self._last = -1

    def begin(self, when=None):
        """Writes the global object and the capture; `when` the UTC time of the first sample
        (core:datetime), None when it is not known."""
        g = {"core:datatype": DATATYPES[self.item], "core:version": SPEC_VERSION}
        if self.sample_rate > 0:
            g["core:sample_rate"] = self.sample_rate
        if self.vlen > 1:  # one stream item (vlen values) is one SigMF sample of vlen channels
            g["core:num_channels"] = self.vlen
        g["core:recorder"] = self.recorder
        g["core:description"] = self.description or (
            "gr-sems recording: one annotation per frame (sems_frame tag) with the frame's truth "
            "(sems_truth) in its sems: fields and every stream tag in sems:tags")
        g["core:extensions"] = [EXTENSION]
        capture = {"core:sample_start": 0}
        if self.frequency:
            capture["core:frequency"] = self.frequency
        if when:
            capture["core:datetime"] = when
        self._file.write('{\n "global": %s,\n "captures": [%s],\n "annotations": ['
                         % (json.dumps(g, indent=1, allow_nan=False).replace("\n", "\n "),
                            json.dumps(capture, allow_nan=False)))

    def add(self, offset, key, value, blob):
        """One tag: its item offset, key, PMT value and pmt.serialize_str(value)."""
        if offset < self._last:
            raise ValueError(f"{self.path}: tags must come in offset order ({offset} after {self._last})")
        self._last = offset
        if self._group and offset != self._at:
            self._close_group()
        self._at = offset
        self._group.append((offset, key, value, blob))

    def finish(self, n_items):
        """Writes the last annotations and closes the file; n_items: the items recorded."""
        if self._file is None:
            return
        if self._group:
            self._close_group()
        self._close_frame(n_items, last=True)
        self._file.write("\n ]\n}\n" if self.annotations else "]\n}\n")
        self._file.close()
        self._file = None

    def _close_group(self):
        offset, tags = self._at, self._group
        self._group = []
        if any(t[1] == FRAME_TAG for t in tags):
            self._close_frame(offset)
            self._frame = [offset, list(tags)]
        elif self._frame and (not self.frame_len or offset < self._frame[0] + self.frame_len):
            self._frame[1].extend(tags)
        else:  # outside every frame: an annotation of its own, one item long
            self._close_frame(offset)
            self._write(offset, 1, tags)

    def _close_frame(self, end, last=False):
        if self._frame is None:
            return
        start, tags = self._frame
        self._frame = None
        count = self.frame_len or end - start
        if last:
            count = max(0, min(count, end - start))
        self._write(start, count, tags)

    def _write(self, start, count, tags):
        a = {"core:sample_start": start, "core:sample_count": count}
        truth = next((v for _, k, v, _ in tags if k == TRUTH_TAG and pmt.is_dict(v)), None)
        fields = truth_fields(truth) if truth is not None else {}
        frame = next((v for _, k, v, _ in tags if k == FRAME_TAG), None)
        if isinstance(fields.get("sems:class_name"), str):
            label = fields["sems:class_name"]
        elif frame is not None:
            label = "frame %s" % (pmt.to_uint64(frame) if pmt.is_uint64(frame) else "")
        else:
            label = "tags"
        a["core:label"] = label.strip()[:20]  # the specification recommends 20 characters at most
        if self.sample_rate > 0 and self.vlen == 1 and self.item == "complex":  # a frame fills the band
            a["core:freq_lower_edge"] = self.frequency - self.sample_rate / 2
            a["core:freq_upper_edge"] = self.frequency + self.sample_rate / 2
        a.update(fields)
        a["sems:tags"] = [{"offset": o, "key": k, "value": base64.b64encode(b).decode("ascii")}
                          for o, k, _, b in tags]
        self._file.write(("\n  " if self.annotations == 0 else ",\n  ") + json.dumps(a, allow_nan=False))
        self.annotations += 1


# ---------------------------------------------------------------------------- reading

def _read_meta(meta_path, who):
    try:
        with open(meta_path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise ValueError(f"{who}: cannot read {meta_path}: {e.strerror} (a SigMF recording is "
                         f"NAME{META} + NAME{DATA}; a JSON-lines tag file's name ends in {TAG_LINES})") from None
    try:
        meta = json.loads(text)
    except ValueError as e:
        raise ValueError(f"{meta_path}: not JSON: {e}") from None
    return meta


def read_recording(path, item="complex", vlen=1, who="tag_file_replay"):
    """Reads the SigMF recording NAME (or NAME.sigmf-meta / NAME.sigmf-data) for a stream of
    `item` x `vlen`: checks its metadata (the specification's required fields and types, the
    datatype and channels against the stream, required extensions) and that its data file
    exists and holds whole items. Returns (tags, n_items): the tags of every annotation's
    sems:tags as (offset, key, pmt value) in offset order (file order within an offset), and
    the items in the data file. A recording made by another tool has no sems:tags: no tags.
    Raises ValueError naming the file and the field."""
    meta_path, data_path = recording_paths(path)
    meta = _read_meta(meta_path, who)
    problems = structure_problems(meta)
    if problems:
        raise ValueError(f"{meta_path}: " + "; ".join(problems))
    g = meta["global"]
    want = DATATYPES[item]
    if g["core:datatype"] != want:
        raise ValueError(f"{meta_path}: core:datatype is {g['core:datatype']!r}; a stream of {item} items "
                         f"replays {want!r} (convert the samples first)")
    channels = g.get("core:num_channels", 1)
    if channels != vlen:
        raise ValueError(f"{meta_path}: core:num_channels is {channels}; the stream's vector length is {vlen}")
    for e in g.get("core:extensions", []):
        if e.get("optional") is False and e.get("name") != EXTENSION["name"]:
            raise ValueError(f"{meta_path}: core:extensions: the recording needs extension "
                             f"{e.get('name')!r}, which gr-sems does not read")
    if g.get("core:trailing_bytes") or any(c.get("core:header_bytes") for c in meta["captures"]):
        raise ValueError(f"{meta_path}: header or trailing bytes in the data file: a File Source "
                         "would read them as samples")
    if "core:dataset" in g:  # a non-conforming dataset, in the same folder
        data_path = os.path.join(os.path.dirname(meta_path), g["core:dataset"])
    try:
        size = os.path.getsize(data_path)
    except OSError as e:
        raise ValueError(f"{data_path}: the recording's data file is missing or unreadable "
                         f"({e.strerror}); {meta_path} describes it") from None
    item_bytes = item_dtype(item, vlen).itemsize
    if size % item_bytes:
        raise ValueError(f"{data_path}: {size} bytes is no whole number of {item}[{vlen}] items "
                         f"({item_bytes} bytes each)")
    n_items = size // item_bytes
    tags = []
    for i, a in enumerate(meta["annotations"]):
        entries = a.get("sems:tags")
        if entries is None:
            continue
        where = f"{meta_path}: annotations[{i}].sems:tags"
        if not isinstance(entries, list):
            raise ValueError(f"{where}: must be an array")
        for j, t in enumerate(entries):
            if not isinstance(t, dict) or set(t) != {"offset", "key", "value"}:
                raise ValueError(f"{where}[{j}]: must be an object of offset, key and value")
            offset, key, value = t["offset"], t["key"], t["value"]
            if not _is_int(offset) or not 0 <= offset < n_items:
                raise ValueError(f"{where}[{j}].offset: must be an item of the data file "
                                 f"(0 to {n_items - 1}), got {offset!r}")
            if not isinstance(key, str) or not key:
                raise ValueError(f"{where}[{j}].key: must be a non-empty string")
            tags.append((offset, key, _deserialize(value, f"{where}[{j}].value")))
    tags.sort(key=lambda t: t[0])
    return tags, n_items


def _deserialize(text, where):
    """A tag value as stored: base64 of pmt.serialize_str."""
    if not isinstance(text, str):
        raise ValueError(f"{where}: must be a base64 string")
    try:
        blob = base64.b64decode(text, validate=True)
    except (ValueError, binascii.Error) as e:
        raise ValueError(f"{where}: not base64: {e}") from None
    return _from_blob(blob, where)


def _from_blob(blob, where):
    try:
        if not blob:
            raise ValueError("empty")
        return pmt.deserialize_str(blob)
    except (ValueError, RuntimeError) as e:
        raise ValueError(f"{where}: not a serialized PMT: {e}") from None


def _read_tag_lines(path):
    """The JSON-lines file's tags as (offset, key, serialized value), in file order."""
    tags = []
    try:
        with open(path, encoding="utf-8") as f:
            for line_no, line in enumerate(f, 1):
                try:
                    d = json.loads(line)
                    offset, key = d["offset"], d["key"]
                    if not _is_int(offset) or offset < 0 or not isinstance(key, str) or not key:
                        raise ValueError("offset must be an integer >= 0, key a non-empty string")
                    tags.append((offset, key, base64.b64decode(d["value"], validate=True)))
                except (ValueError, KeyError, TypeError, binascii.Error) as e:
                    raise ValueError(f"{path}:{line_no}: not a tag line: {e}") from None
    except OSError as e:
        raise ValueError(f"tag_file_replay: cannot read {path}: {e.strerror}") from None
    return tags


def read_tags(path, item="complex", vlen=1):
    """The tags of a recording as (offset, key, pmt value), in offset order: of the SigMF
    recording NAME (read_recording, checked against a stream of `item` x `vlen`), or of a
    JSON-lines tag file of earlier versions (a name ending in .tags; tags at one offset in file order).
    Raises ValueError naming the file and the line or field."""
    if not is_tag_lines(path):
        return read_recording(path, item, vlen)[0]
    tags = []
    for line_no, (offset, key, blob) in enumerate(_read_tag_lines(path), 1):
        tags.append((offset, key, _from_blob(blob, f"{path}:{line_no}")))
    tags.sort(key=lambda t: t[0])
    return tags


# ---------------------------------------------------------------------------- checking

def _type_ok(v, kind):
    return {_INT: _is_int, _NUM: _is_num, _STR: lambda x: isinstance(x, str),
            _BOOL: lambda x: isinstance(x, bool), _OBJ: lambda x: isinstance(x, dict),
            _LIST: lambda x: isinstance(x, list)}[kind](v)


def _segments(meta, name, problems):
    """The captures or annotations array: objects with an integer core:sample_start >= 0,
    sorted by it."""
    seg = meta[name]
    if not isinstance(seg, list):
        problems.append(f"{name}: must be an array")
        return []
    last = -1
    for i, s in enumerate(seg):
        if not isinstance(s, dict):
            problems.append(f"{name}[{i}]: must be an object")
            continue
        start = s.get("core:sample_start")
        if not _is_int(start) or not 0 <= start <= _INDEX_MAX:
            problems.append(f"{name}[{i}].core:sample_start: required, an integer >= 0, got {start!r}")
            continue
        if start < last:
            problems.append(f"{name}[{i}].core:sample_start: {start} after {last}: the {name} must be "
                            "sorted by core:sample_start")
        last = start
        count = s.get("core:sample_count")
        if name == "annotations" and "core:sample_count" in s and (not _is_int(count) or count < 0):
            problems.append(f"{name}[{i}].core:sample_count: must be an integer >= 0, got {count!r}")
    return [s for s in seg if isinstance(s, dict)]


def structure_problems(meta):
    """What a reader needs (the specification's REQUIRED fields and their types): a top-level
    object of global, captures and annotations; global core:datatype and core:version;
    captures and annotations sorted by an integer core:sample_start; an annotation's
    core:sample_count an integer >= 0; core:num_channels an integer >= 1 and core:extensions
    objects of name, version and optional. A list of problems, empty when none."""
    if not isinstance(meta, dict):
        return ["the metadata must be a JSON object"]
    problems = [f"{k}: required" for k in ("global", "captures", "annotations") if k not in meta]
    if problems:
        return problems
    g = meta["global"]
    if not isinstance(g, dict):
        return ["global: must be an object"]
    dt, version = g.get("core:datatype"), g.get("core:version")
    if not isinstance(dt, str) or not _DATATYPE.match(dt):
        problems.append(f"global.core:datatype: required, a SigMF dataset format such as 'cf32_le', got {dt!r}")
    if not isinstance(version, str) or not _VERSION.match(version):
        problems.append(f"global.core:version: required, the specification's version X.Y.Z, got {version!r}")
    channels = g.get("core:num_channels", 1)
    if not _is_int(channels) or channels < 1:
        problems.append(f"global.core:num_channels: must be an integer >= 1, got {channels!r}")
    extensions = g.get("core:extensions", [])
    if not isinstance(extensions, list):
        problems.append("global.core:extensions: must be an array")
    else:
        for i, e in enumerate(extensions):
            if (not isinstance(e, dict) or set(e) != {"name", "version", "optional"}
                    or not isinstance(e["name"], str) or not isinstance(e["version"], str)
                    or not isinstance(e["optional"], bool)):
                problems.append(f"global.core:extensions[{i}]: must be an object of exactly name (string), "
                                "version (string) and optional (boolean)")
    _segments(meta, "captures", problems)
    _segments(meta, "annotations", problems)
    return problems


def _datetime_problem(text):
    m = _DATETIME.match(text) if isinstance(text, str) else None
    if not m:
        return "must be RFC 3339 in UTC, YYYY-MM-DDTHH:MM:SS[.fraction]Z"
    year, month, day, hour, minute, second = (int(x) for x in m.groups()[:6])
    if not (1 <= month <= 12 and 1 <= day <= calendar.monthrange(year, month)[1]
            and hour <= 23 and minute <= 59 and second <= 60):
        return "not a valid date and time"
    return None


def problems(meta):
    """Every way `meta` (a parsed .sigmf-meta) breaks the SigMF specification's rules for a
    compliant recording: structure_problems, and every field named namespace:name with a
    declared namespace (core or one of core:extensions) and a name of letters, digits and _
    that is no C++20 or Python keyword; the core fields known to their object with their
    types and ranges (sample rate 1 Hz to 1 THz, frequencies within 1 THz, indices >= 0);
    core:datetime in RFC 3339 UTC; an annotation's frequency edges both or neither. An empty
    list for a compliant file."""
    found = structure_problems(meta)
    if found:
        return found
    unknown = [k for k in meta if k not in ("global", "captures", "annotations")]
    found += [f"{k}: not a top-level object of SigMF" for k in unknown]
    g = meta["global"]
    declared = {"core"} | {e["name"] for e in g.get("core:extensions", [])}
    objects = [("global", g)] + [(f"{name}[{i}]", s) for name in ("captures", "annotations")
                                 for i, s in enumerate(meta[name])]
    for where, obj in objects:
        kind = where.split("[")[0]
        for field, value in obj.items():
            namespace, sep, name = field.partition(":")
            if not sep or not namespace or not _valid_name(name):
                found.append(f"{where}.{field}: a field name must be namespace:name, the name of letters, "
                             "digits and _ and no C++ or Python keyword")
                continue
            if namespace not in declared:
                found.append(f"{where}.{field}: namespace {namespace!r} is not declared in core:extensions")
                continue
            if namespace != "core":
                continue
            kinds = _CORE[kind]
            if name not in kinds:
                found.append(f"{where}.{field}: not a core field of the {kind} object")
            elif not _type_ok(value, kinds[name]):
                found.append(f"{where}.{field}: must be of type {kinds[name]}, got {value!r}")
            elif name == "sample_rate" and not 1 <= value <= _FREQ_MAX:
                found.append(f"{where}.{field}: must be between 1 and 1e12, got {value!r}")
            elif name in ("frequency", "freq_lower_edge", "freq_upper_edge") and not (
                    math.isfinite(value) and abs(value) <= _FREQ_MAX):
                found.append(f"{where}.{field}: must be within +-1e12, got {value!r}")
            elif kinds[name] == _INT and not 0 <= value <= _INDEX_MAX:
                found.append(f"{where}.{field}: must be an integer >= 0, got {value!r}")
            elif name == "datetime" and _datetime_problem(value):
                found.append(f"{where}.{field}: {_datetime_problem(value)}, got {value!r}")
        if kind == "annotations" and ("core:freq_lower_edge" in obj) != ("core:freq_upper_edge" in obj):
            found.append(f"{where}: core:freq_lower_edge and core:freq_upper_edge go together")
    return found


def check(path):
    """Checks the recording NAME's metadata against the specification (problems()) and that
    its data file exists; raises ValueError naming the file and listing every problem."""
    meta_path, data_path = recording_paths(path)
    meta = _read_meta(meta_path, "check")
    found = problems(meta)
    if found:
        raise ValueError(f"{meta_path}: not compliant SigMF:\n  " + "\n  ".join(found))
    if "core:dataset" in meta["global"]:
        data_path = os.path.join(os.path.dirname(meta_path), meta["global"]["core:dataset"])
    if not meta["global"].get("core:metadata_only") and not os.path.isfile(data_path):
        raise ValueError(f"{data_path}: the recording's data file is missing; {meta_path} describes it")
    return meta_path


# ---------------------------------------------------------------------------- converting

def convert(raw, tags=None, out=None, item="complex", vlen=1, sample_rate=0.0, frequency=0.0,
            frame_len=0, description=""):
    """Converts a raw recording with its JSON-lines tag file (tags; default RAW.tags) into the
    SigMF recording `out` (default: RAW without its extension): copies the samples to
    OUT.sigmf-data and writes OUT.sigmf-meta with the same tags, bit for bit, as the sink would
    have. The recording's time is not known: no core:datetime. Refuses to overwrite either
    file. Returns the metadata file's path."""
    vlen, sample_rate, frequency, frame_len = check_settings("convert", item, vlen, sample_rate, frequency,
                                                             frame_len)
    tags = tags or raw + TAG_LINES
    out = out or os.path.splitext(raw)[0]
    meta_path, data_path = recording_paths(out)
    for p in (meta_path, data_path):
        if os.path.exists(p):
            raise ValueError(f"convert: {p} exists; choose another output name")
    try:
        size = os.path.getsize(raw)
    except OSError as e:
        raise ValueError(f"convert: cannot read {raw}: {e.strerror}") from None
    item_bytes = item_dtype(item, vlen).itemsize
    if size % item_bytes:
        raise ValueError(f"{raw}: {size} bytes is no whole number of {item}[{vlen}] items ({item_bytes} bytes each)")
    n_items = size // item_bytes
    lines = sorted(_read_tag_lines(tags), key=lambda t: t[0])
    for offset, key, _ in lines:
        if offset >= n_items:
            raise ValueError(f"{tags}: tag {key!r} at offset {offset}, past the {n_items} items of {raw}")
    values = [_from_blob(b, f"{tags}: tag at offset {o}") for o, _, b in lines]
    try:
        shutil.copyfile(raw, data_path)
        writer = meta_writer(meta_path, item, vlen, sample_rate, frequency, frame_len, description,
                             recorder="gr-sems sigmf convert")
    except OSError as e:
        raise ValueError(f"convert: cannot write {e.filename}: {e.strerror}") from None
    writer.begin(None)
    for (offset, key, blob), value in zip(lines, values):
        writer.add(offset, key, value, blob)
    writer.finish(n_items)
    return meta_path


def check_settings(who, item, vlen, sample_rate=0.0, frequency=0.0, frame_len=0):
    """The recording settings of the sink and the converter as (vlen, sample_rate, frequency,
    frame_len) of Python int and float; ValueError naming the parameter."""
    def integer(v):
        return isinstance(v, numbers.Integral) and not isinstance(v, (bool, np.bool_))

    def real(v):
        return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) and math.isfinite(v)

    if item not in DATATYPES:
        raise ValueError(f"{who}: item must be 'complex' or 'float', got {item!r}")
    if not integer(vlen) or vlen < 1:
        raise ValueError(f"{who}: vlen must be an integer >= 1, got {vlen!r}")
    if not real(sample_rate) or not (sample_rate == 0 or 1 <= sample_rate <= _FREQ_MAX):
        raise ValueError(f"{who}: sample_rate must be 0 (not recorded) or 1 to 1e12 S/s, got {sample_rate!r}")
    if not real(frequency) or abs(frequency) > _FREQ_MAX:
        raise ValueError(f"{who}: frequency must be a finite number within +-1e12 Hz, got {frequency!r}")
    if not integer(frame_len) or frame_len < 0:
        raise ValueError(f"{who}: frame_len must be an integer >= 0 (0: frames end at the next "
                         f"sems_frame tag), got {frame_len!r}")
    return int(vlen), float(sample_rate), float(frequency), int(frame_len)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m gnuradio.sems.sigmf",
                                description="SigMF recordings of gr-sems: convert a raw recording with "
                                            "its .tags file, or check a .sigmf-meta file.")
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("convert", help="raw samples + JSON-lines tag file -> NAME.sigmf-data + NAME.sigmf-meta")
    c.add_argument("raw", help="the raw recording (File Sink's samples)")
    c.add_argument("--tags", help="its tag file (default: RAW.tags)")
    c.add_argument("--out", help="the SigMF recording's name (default: RAW without its extension)")
    c.add_argument("--item", choices=sorted(DATATYPES), default="complex")
    c.add_argument("--vlen", type=int, default=1, help="values per stream item (default 1)")
    c.add_argument("--sample-rate", type=float, default=0.0, help="S/s (default 0: not recorded)")
    c.add_argument("--frequency", type=float, default=0.0, help="centre frequency in Hz (default 0: not recorded)")
    c.add_argument("--frame-len", type=int, default=0,
                   help="items per frame (default 0: a frame ends at the next sems_frame tag)")
    c.add_argument("--description", default="")
    k = sub.add_parser("check", help="checks NAME.sigmf-meta against the SigMF specification")
    k.add_argument("recording", help="NAME, NAME.sigmf-meta or NAME.sigmf-data")
    args = p.parse_args(argv)
    try:
        if args.command == "convert":
            meta = convert(args.raw, args.tags, args.out, args.item, args.vlen, args.sample_rate,
                           args.frequency, args.frame_len, args.description)
            print(f"wrote {recording_paths(meta)[1]} and {meta}")
        else:
            print(f"{check(args.recording)}: keeps the rules of SigMF {SPEC_VERSION}")
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
