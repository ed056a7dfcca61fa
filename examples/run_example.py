#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: compile an example flowgraph with grcc and run it (headless, or a GUI one on a display).

    run_example.py <flowgraph.grc> <outdir> [--test] [--frames K] [--timeout S] [--compiled DIR] [-- extra args for the flowgraph]

The flowgraph is compiled into <outdir>/<name>/ (or, with --compiled DIR, taken from DIR, where
`grcc -o DIR` compiled it before: CTest compiles every example in one grcc call) and the generated Python runs with
GNU Radio's interpreter (/usr/bin/python3). With <outdir> inside a build tree of this source
(e.g. build/examples), it finds the blocks and the module there: PYTHONPATH, GRC_BLOCKS_PATH
and SEMS_SOURCE_DIR default to <build>/python_pkg, the source's grc/ and the source tree (a
value already set wins). With --test, a flowgraph that has a
`frames` parameter runs --frames frames (default 1000), and a printed
"set_snr_db=X measured_snr_db=Y" must agree within ±0.5 dB; without it the flowgraph's output
shows as it comes. A run is abandoned after --timeout seconds (600; 0: never, for a GUI
flowgraph that runs until its window is closed). Exits non-zero on failure.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

import yaml

GR_PYTHON = "/usr/bin/python3"
SNR_TOLERANCE_DB = 0.5
SNR_LINE = re.compile(r"set_snr_db=(\S+)\s+measured_snr_db=(\S+)")


def fail(message):
    print(f"run_example: {message}", file=sys.stderr)
    sys.exit(1)


def flowgraph_info(grc_path):
    """(generated script name, parameter names) from the .grc file."""
    try:
        with open(grc_path) as f:
            doc = yaml.safe_load(f)
        script = doc["options"]["parameters"]["id"] + ".py"
        params = {b["name"] for b in doc.get("blocks", []) if b.get("id") == "parameter"}
    except (OSError, yaml.YAMLError, KeyError, TypeError) as e:
        fail(f"{grc_path}: cannot read the flowgraph: {e}")
    return script, params


def source_tree_defaults(outdir):
    """Environment for a source-tree run: the Python package of the build tree that holds
    outdir (the nearest folder up with a CMakeCache.txt), the source's GRC blocks and models.
    Variables already set are kept."""
    source = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    build = os.path.abspath(outdir)
    while not os.path.isfile(os.path.join(build, "CMakeCache.txt")) and os.path.dirname(build) != build:
        build = os.path.dirname(build)
    python_pkg = os.path.join(build, "python_pkg")
    if not (os.path.isdir(os.path.join(source, "grc")) and os.path.isdir(os.path.join(python_pkg, "gnuradio", "sems"))):
        return env  # not a build tree of this source: the module must be on the default paths
    defaults = {"PYTHONPATH": python_pkg, "GRC_BLOCKS_PATH": os.path.join(source, "grc"),
                "SEMS_SOURCE_DIR": source}
    for key, value in defaults.items():
        env.setdefault(key, value)
    return env


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("grc")
    parser.add_argument("outdir")
    parser.add_argument("--test", action="store_true", help="short run with the example's checks")
    parser.add_argument("--frames", type=int, default=1000, help="frames for --test (default 1000)")
    parser.add_argument("--timeout", type=float, default=600.0, help="seconds before the run is abandoned (0: never)")
    parser.add_argument("--compiled", metavar="DIR",
                        help="run DIR/<id>.py, compiled before (grcc -o DIR ...), instead of compiling into OUTDIR")
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)

    if not os.path.isfile(args.grc):
        fail(f"{args.grc}: no such flowgraph")
    script, params = flowgraph_info(args.grc)

    env = source_tree_defaults(args.outdir)
    if args.compiled:
        outdir = args.compiled
        if not os.path.isfile(os.path.join(outdir, script)):
            fail(f"--compiled {outdir}: no {script} there (grcc -o {outdir} {args.grc} writes it)")
    else:
        outdir = os.path.join(args.outdir, os.path.splitext(os.path.basename(args.grc))[0])
        os.makedirs(outdir, exist_ok=True)
        grcc = shutil.which("grcc") or "/usr/bin/grcc"
        compiled = subprocess.run([grcc, "-o", outdir, args.grc], capture_output=True, text=True, env=env)
        if compiled.returncode != 0 or not os.path.isfile(os.path.join(outdir, script)):
            sys.stderr.write(compiled.stdout + compiled.stderr)
            fail(f"grcc could not compile {args.grc}")

    cmd = [GR_PYTHON, "-u", os.path.join(outdir, script)]
    if args.test and "frames" in params:
        cmd += ["--frames", str(args.frames)]
    cmd += extra
    print("run_example:", " ".join(cmd), flush=True)
    try:
        ran = subprocess.run(cmd, capture_output=args.test, text=True, timeout=args.timeout or None, env=env)
    except subprocess.TimeoutExpired:
        fail(f"{script} did not finish within {args.timeout:.0f} s")
    if args.test:
        sys.stdout.write(ran.stdout)
        sys.stderr.write(ran.stderr)
    if ran.returncode != 0:
        fail(f"{script} exited with {ran.returncode}")

    if args.test:
        for set_db, measured_db in SNR_LINE.findall(ran.stdout):
            if not abs(float(measured_db) - float(set_db)) <= SNR_TOLERANCE_DB:
                fail(f"measured SNR {measured_db} dB is not within ±{SNR_TOLERANCE_DB} dB of the set {set_db} dB")
            print(f"run_example: measured SNR {measured_db} dB matches the set {set_db} dB "
                  f"(±{SNR_TOLERANCE_DB} dB)")


if __name__ == "__main__":
    main()
