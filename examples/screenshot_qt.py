#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: compile a Qt GUI example flowgraph with grcc, run it for a few seconds
(headless with QT_QPA_PLATFORM=offscreen) and save a screenshot of its window.

    screenshot_qt.py <flowgraph.grc> <outdir> <screenshot.png> [--seconds S] [--size WxH]
                     [--check EXPR]

Fails (exit 1) if the flowgraph does not compile, raises, the screenshot is empty
(every pixel the same colour), or the Python expression EXPR (evaluated with the running
top block as `tb` when the screenshot is taken, e.g. "tb.classifier.frames() >= 2") is false.
"""
import argparse
import importlib.util
import os
import shutil
import subprocess
import sys

import yaml


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("grc")
    ap.add_argument("outdir")
    ap.add_argument("png")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--size", default="1000x520", help="window size in pixels, WxH (default 1000x520)")
    ap.add_argument("--check", default="", help="expression on the top block `tb` that must hold at the screenshot")
    args = ap.parse_args()
    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
        if width < 1 or height < 1:
            raise ValueError
    except ValueError:
        sys.exit(f"screenshot_qt: --size must be WxH in pixels, got {args.size!r}")

    with open(args.grc) as f:
        script_id = yaml.safe_load(f)["options"]["parameters"]["id"]
    outdir = os.path.join(args.outdir, script_id)
    os.makedirs(outdir, exist_ok=True)
    grcc = shutil.which("grcc") or "/usr/bin/grcc"
    done = subprocess.run([grcc, "-o", outdir, args.grc], capture_output=True, text=True)
    script = os.path.join(outdir, script_id + ".py")
    if done.returncode != 0 or not os.path.isfile(script):
        sys.stderr.write(done.stdout + done.stderr)
        sys.exit(f"screenshot_qt: grcc could not compile {args.grc}")

    sys.path.insert(0, outdir)  # grcc writes embedded Python blocks next to the script
    spec = importlib.util.spec_from_file_location(script_id, script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    from PyQt5 import Qt, QtCore

    app = Qt.QApplication([script_id])
    tb = getattr(module, script_id)()
    tb.start()
    tb.show()
    tb.resize(width, height)

    def shoot():
        image = tb.grab().toImage()
        colours = {image.pixel(x, y) for x in range(0, image.width(), 7) for y in range(0, image.height(), 7)}
        os.makedirs(os.path.dirname(os.path.abspath(args.png)), exist_ok=True)
        if not image.save(args.png):
            print(f"screenshot_qt: cannot write {args.png}", file=sys.stderr)
            app.exit(1)
        elif len(colours) < 3:
            print(f"screenshot_qt: {args.png} is blank ({len(colours)} colours)", file=sys.stderr)
            app.exit(1)
        elif args.check and not eval(args.check, {"tb": tb}):
            print(f"screenshot_qt: saved {args.png}, but at {args.seconds:g} s this is false: {args.check}",
                  file=sys.stderr)
            app.exit(1)
        else:
            print(f"screenshot_qt: saved {args.png} ({image.width()}x{image.height()}, {len(colours)} colours)")
            app.exit(0)

    QtCore.QTimer.singleShot(int(args.seconds * 1000), shoot)
    rc = app.exec_()
    tb.stop()
    tb.wait()
    sys.exit(rc)


if __name__ == "__main__":
    main()
