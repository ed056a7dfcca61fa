#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: a hardware example (SoapySDR TX and RX on one device) with its radio simulated.

    run_sdr_sim.py <flowgraph.grc> <outdir> [--scene cable|random] [checks] [-- flowgraph args]

The twin of the flowgraph is written to <outdir>/<name>_sim.grc: the same file with the Soapy
sink and source replaced by SemS Radio Front End (the ideal radio, the frame preset of the
flowgraph's `frame`) followed by a delay of `--sim-latency` samples (GNU Radio's Delay), which
stands for the radio's unknown TX-to-RX latency. Every other block, parameter and check stays
as shipped. The twin gets two parameters: `sim_latency` (samples) and `sim_snr_db` (SNR per
resource element).

--scene cable: one still point at range 0 (a cable: the latency and noise alone);
--scene random: a random target of the frame's class library per frame, with its truth tags.

Checks on the printed summary (the flowgraph's own checks run too):
  --expect-latency K   `latency=` must be K (the calibration found the latency to the sample)
  --write-latency F    writes the `latency=` found to F
  --latency-file F     passes `--latency <the number in F>` to the flowgraph
  --min-accuracy A     every frame classified and scored against its truth, accuracy >= A

The twin is compiled and run by run_example.py. Exits non-zero on failure.
"""
import argparse
import json
import os
import re
import subprocess
import sys

import yaml

CABLE_SCENE = {"format": "sems.scene", "version": 1, "classes": "kinematic", "fading": "none",
               "description": "a cable: one still point at range 0",
               "targets": [{"class": "car", "range_m": 0, "speed_mps": 0, "heading_rad": 0,
                            "micro_motion": {"model": "sinusoid", "rate_hz": 1, "amplitude_m": 0}}]}


def fail(message):
    print(f"run_sdr_sim: {message}", file=sys.stderr)
    sys.exit(1)


def block(name, block_id, params, coordinate):
    return {"name": name, "id": block_id, "parameters": dict(params, comment=""),
            "states": {"bus_sink": False, "bus_source": False, "bus_structure": None,
                       "coordinate": list(coordinate), "rotation": 0, "state": "enabled"}}


def twin(doc, scene):
    """The flowgraph with its Soapy sink and source replaced by radio_front_end + a delay."""
    radios = [b for b in doc["blocks"] if b["id"].startswith("soapy_")]
    tx = [b["name"] for b in radios if b["id"].endswith("_sink")]
    rx = [b["name"] for b in radios if b["id"].endswith("_source")]
    if len(tx) != 1 or len(rx) != 1:
        fail(f"expected one Soapy sink and one Soapy source, found sinks {tx} and sources {rx}")
    tx, rx = tx[0], rx[0]
    doc["blocks"] = [b for b in doc["blocks"] if b["name"] not in (tx, rx)]
    doc["options"]["parameters"]["id"] += "_sim"
    fe = {"radio": "''", "settings": "{}", "tx_power": "(M - len(sems.frame_of(frame).guard_subcarriers)) / M",
          "scene_kind": "random", "scene_file": "''", "class_library": "sems.frame_file.find(frame).classes",
          "classes": "[]", "n_targets": "1", "snr_db": "sim_snr_db", "seed": "seed", "frame": "frame",
          "cp_len": "cp_len", "affinity": "", "alias": "", "maxoutbuf": "0", "minoutbuf": "0"}
    if scene == "cable":
        fe.update(scene_kind="file", scene_file=repr(json.dumps(CABLE_SCENE)))
    doc["blocks"] += [
        block("sim_latency", "parameter", {"label": "Simulated radio latency (samples)", "short_id": "",
                                           "type": "intx", "value": "0", "hide": "none"}, (1000, 700)),
        block("sim_snr_db", "parameter", {"label": "Simulated SNR (dB)", "short_id": "", "type": "eng_float",
                                          "value": "30", "hide": "none"}, (1150, 700)),
        block("sim_radio", "sems_radio_front_end", fe, (1000, 200)),
        block("sim_delay", "blocks_delay", {"type": "complex", "delay": "sim_latency", "num_ports": "1",
                                            "vlen": "1", "showports": "False", "affinity": "", "alias": "",
                                            "maxoutbuf": "0", "minoutbuf": "0"}, (1000, 400)),
    ]
    connections = [["sim_radio", "0", "sim_delay", "0"]]
    for c in doc["connections"]:
        if c[2] == tx:
            connections.append([c[0], c[1], "sim_radio", "0"])
        elif c[0] == rx:
            connections.append(["sim_delay", "0", c[2], c[3]])
        else:
            connections.append(c)
    doc["connections"] = connections
    return doc


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("grc")
    parser.add_argument("outdir")
    parser.add_argument("--scene", choices=["cable", "random"], default="random")
    parser.add_argument("--expect-latency", type=int)
    parser.add_argument("--write-latency")
    parser.add_argument("--latency-file")
    parser.add_argument("--min-accuracy", type=float)
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)

    try:
        with open(args.grc) as f:
            doc = yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as e:
        fail(f"{args.grc}: cannot read the flowgraph: {e}")
    doc = twin(doc, args.scene)
    os.makedirs(args.outdir, exist_ok=True)
    twin_grc = os.path.join(args.outdir, doc["options"]["parameters"]["id"] + ".grc")
    with open(twin_grc, "w") as f:
        yaml.safe_dump(doc, f, sort_keys=False)

    if args.latency_file:
        try:
            with open(args.latency_file) as f:
                extra = ["--latency", str(int(f.read().strip()))] + extra
        except (OSError, ValueError) as e:
            fail(f"{args.latency_file}: cannot read a latency: {e}")
    cmd = [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "run_example.py"),
           twin_grc, args.outdir, "--"] + extra
    ran = subprocess.run(cmd, capture_output=True, text=True)
    sys.stdout.write(ran.stdout)
    sys.stderr.write(ran.stderr)
    if ran.returncode != 0:
        fail(f"the twin of {os.path.basename(args.grc)} failed")

    latency = re.search(r"latency=(-?\d+)", ran.stdout)
    if args.expect_latency is not None or args.write_latency:
        if not latency:
            fail("no latency= in the flowgraph's output")
        found = int(latency.group(1))
        if args.expect_latency is not None and found != args.expect_latency:
            fail(f"the calibration found a latency of {found} samples, the simulated radio's is {args.expect_latency}")
        if args.write_latency:
            with open(args.write_latency, "w") as f:
                f.write(f"{found}\n")
    if args.min_accuracy is not None:
        m = re.search(r"frames=(\d+) classified=(\d+) scored=(\d+) accuracy=(\S+)", ran.stdout)
        if not m:
            fail("no classifier summary in the flowgraph's output")
        frames, classified, scored, accuracy = int(m[1]), int(m[2]), int(m[3]), float(m[4])
        if not (frames == classified == scored):
            fail(f"{frames} frames sent, {classified} classified, {scored} scored against their truth")
        if not accuracy >= args.min_accuracy:
            fail(f"accuracy {accuracy:.4f} over {scored} frames, below the minimum {args.min_accuracy}")
    print("run_sdr_sim: passed", flush=True)


if __name__ == "__main__":
    main()
