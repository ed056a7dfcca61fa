#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Trains a tiny classifier on one frame preset and loads it into the classifier sink.

    check_frame_preset.py SEMS_TRAIN PRESET OUT_DIR [--symbols N] [--frames F]

- sems_train --frame PRESET (a few hundred frames, one epoch, a fixed seed) must succeed,
  print the frame it uses and record it in bundle.json;
- the learned mask keeps off the preset's guard subcarriers;
- sems.classifier_sink loads the bundle with the same frame;
- a frame that differs in one field is refused, the error naming the field and both values.

--symbols N trains on the preset with fewer symbols and --frames F on fewer frames (the
large presets, to keep the test short); the sink then gets that frame as a frame file.
"""
import argparse
import json
import os
import subprocess
import sys

from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), ".."))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("sems_train")
    ap.add_argument("preset")
    ap.add_argument("out")
    ap.add_argument("--symbols", type=int)
    ap.add_argument("--frames", type=int, default=200)
    a = ap.parse_args()

    os.makedirs(a.out, exist_ok=True)
    preset = json.load(open(os.path.join(SOURCE, "models", "frames", a.preset + ".json")))
    want = dict(preset["frame"])
    cmd = [a.sems_train, "--task", "classify", "--frame", a.preset, "--frames", str(a.frames), "--epochs", "1",
           "--decoder-epochs", "0", "--batch", "50", "--threads", "1", "--seed", "5", "--pilots", "16",
           "--width", "4", "--hidden", "16", "--range-bins", "8", "--eval-snr", "20", "--quiet",
           "--out", os.path.join(a.out, "bundle")]
    if a.symbols:
        cmd += ["--symbols", str(a.symbols)]
        want["n_symbols"] = a.symbols
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
    first = run.stdout.splitlines()[0]
    assert first.startswith("frame " + a.preset), f"sems_train did not print the frame first: {first!r}"

    bundle_dir = os.path.join(a.out, "bundle")
    bundle = json.load(open(os.path.join(bundle_dir, "bundle.json")))
    got = sems.frame_file.from_json_string(json.dumps({"format": "sems.frame", "version": 1,
                                                       "frame": bundle["frame"]}), "bundle")
    expected = sems.frame_file.from_json_string(json.dumps({"format": "sems.frame", "version": 1,
                                                            "frame": want}), "preset")
    assert got.frame == expected.frame, f"bundle frame {bundle['frame']} != preset {want}"

    mask = json.load(open(os.path.join(bundle_dir, "mask.json")))
    guards = set(expected.frame.guard_subcarriers)
    # Every subcarrier is used only in the paper's frame and in a sensing grid sampled inside a
    # carrier's used band (nr_sensing_120khz: every 4th subcarrier, no DC or band edge among them);
    # the radios' presets leave DC and the band edges empty, and no pilot may land there.
    assert guards or a.preset in ("paper", "nr_sensing_120khz"), f"{a.preset} has no guard subcarriers"
    on_guard = [p for p in mask["pilots"] if p[1] in guards]
    assert not on_guard, f"learned pilots on guard subcarriers: {on_guard}"

    n, m = want["n_symbols"], want["n_subcarriers"]
    if a.symbols:  # the changed frame, as a frame file
        frame_arg = os.path.join(a.out, "frame.json")
        json.dump({"format": "sems.frame", "version": 1, "name": a.preset + "_small", "frame": want},
                  open(frame_arg, "w"))
    else:
        frame_arg = a.preset
    sink = sems.classifier_sink(bundle_dir, 16, 8, 1, 0, n, m, frame_arg)
    assert sink.class_names(), "the sink has no classes"

    # One field changed: refused, naming it and both values.
    other = dict(want, carrier_hz=want["carrier_hz"] * 2)
    other_path = os.path.join(a.out, "other.json")
    json.dump({"format": "sems.frame", "version": 1, "name": "other", "frame": other}, open(other_path, "w"))
    try:
        sems.classifier_sink(bundle_dir, 16, 8, 1, 0, n, m, other_path)
    except Exception as e:  # pybind11 turns std::invalid_argument into ValueError
        text = str(e)
        for needle in ("carrier_hz", repr_number(want["carrier_hz"]), repr_number(other["carrier_hz"])):
            assert needle in text, f"the refusal {text!r} lacks {needle!r}"
    else:
        sys.exit("a bundle was loaded into a sink on another carrier")
    print(f"{a.preset}: trained on {n} x {m}, loaded into classifier_sink, other carrier refused")


def repr_number(x):
    """As the module prints a number: the shortest text that reads back the same."""
    for digits in (15, 17):
        t = f"{x:.{digits}g}"
        if float(t) == x:
            return t
    return t


if __name__ == "__main__":
    main()
