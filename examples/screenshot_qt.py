#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: compile a Qt GUI example flowgraph with grcc, run it for a few seconds
(headless with QT_QPA_PLATFORM=offscreen) and save a screenshot of its window.

    screenshot_qt.py <flowgraph.grc> <outdir> <screenshot.png> [--seconds S] [--size WxH]
                     [--check EXPR] [--cycles K [--cycle-seconds S] [--cycle-speed F]
                     [--cycle-check EXPR]] [--compiled DIR]

(--compiled DIR: the flowgraph as `grcc -o DIR` compiled it before, as CTest does for every
example in one call, instead of compiling it into <outdir>/<id>/.)

Each run does what the generated script's main() does (the flowgraph's Python snippets
included), then tears the flowgraph and its window down in the order GNU Radio's Qt sinks
need: flowgraph stopped, blocks freed while their widgets still exist, then the window.
With --cycles K, K - 1 stress cycles come first in the same process: each builds, starts and
shows the flowgraph, runs it for --cycle-seconds with its throttles --cycle-speed times faster
while the window repaints without pause (a widget touched from a GNU Radio thread then races
with Qt's painting all the time, not only at the sinks' update rate), waits for --cycle-check
to hold, and tears it all down again.

Fails (exit 1) if the flowgraph does not compile, raises, the screenshot is empty
(every pixel the same colour), or the Python expression EXPR (evaluated with the running
top block as `tb` when the screenshot is taken, e.g. "tb.classifier.frames() >= 2") is false;
a crash in any cycle ends the process with the signal.
"""
import argparse
import gc
import importlib.util
import os
import shutil
import subprocess
import sys
import time

import yaml

CYCLE_GRACE_S = 30.0  # the longest a stress cycle may run past --cycle-seconds for its check

def fail(message):
    print(f"screenshot_qt: {message}", file=sys.stderr)
    sys.exit(1)


def compile_flowgraph(grc, outdir, compiled=None):
    """The generated module of `grc` (compiled by grcc into <outdir>/<id>/, or taken from
    `compiled`, where `grcc -o compiled` wrote it before) and its id."""
    with open(grc) as f:
        script_id = yaml.safe_load(f)["options"]["parameters"]["id"]
    if compiled:
        outdir = compiled
        script = os.path.join(outdir, script_id + ".py")
        if not os.path.isfile(script):
            fail(f"--compiled {outdir}: no {script_id}.py there (grcc -o {outdir} {grc} writes it)")
    else:
        outdir = os.path.join(outdir, script_id)
        os.makedirs(outdir, exist_ok=True)
        grcc = shutil.which("grcc") or "/usr/bin/grcc"
        done = subprocess.run([grcc, "-o", outdir, grc], capture_output=True, text=True)
        script = os.path.join(outdir, script_id + ".py")
        if done.returncode != 0 or not os.path.isfile(script):
            sys.stderr.write(done.stdout + done.stderr)
            fail(f"grcc could not compile {grc}")
    sys.path.insert(0, outdir)  # grcc writes embedded Python blocks next to the script
    spec = importlib.util.spec_from_file_location(script_id, script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module, script_id


def snippets(module, section, tb):
    """The flowgraph's Python snippets of one section, as its main() calls them."""
    run = getattr(module, "snippets_" + section, None)
    if run is not None:
        run(tb)


def holds(expr, tb, quiet=False):
    """Whether the check `expr` (empty: none) holds on the top block; an error in it is false."""
    try:
        return not expr or bool(eval(expr, {"tb": tb}))
    except Exception as e:
        if not quiet:
            print(f"screenshot_qt: {expr}: {type(e).__name__}: {e}", file=sys.stderr)
        return False


def start(module, script_id, width, height):
    """The top block built, started and shown as the generated main() does it."""
    tb = getattr(module, script_id)()
    snippets(module, "main_after_init", tb)
    tb.start()
    snippets(module, "main_after_start", tb)
    tb.show()
    tb.resize(width, height)
    return tb


def tear_down(module, tb, app):
    """Stop the flowgraph, free its blocks, then delete its window.

    GNU Radio's Qt sinks close their display widget in their destructor, and that widget
    belongs to the window (the flowgraph added it to its layout): the blocks must go while the
    window still exists. The top block holds them in its graph and in its attributes; Message
    Pair to Variable holds a setter of the window, hence the window itself."""
    import sip

    tb.stop()
    tb.wait()
    snippets(module, "main_after_stop", tb)
    tb.disconnect_all()
    for name in [k for k, v in vars(tb).items() if k == "_impl" or hasattr(v, "to_basic_block")]:
        delattr(tb, name)
    gc.collect()
    tb.hide()
    sip.delete(tb)
    app.processEvents()  # whatever the window still had queued, now dropped


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("grc")
    ap.add_argument("outdir")
    ap.add_argument("png")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--compiled", metavar="DIR", help="take DIR/<id>.py, compiled before (grcc -o DIR ...), instead of compiling")
    ap.add_argument("--size", default="1000x520", help="window size in pixels, WxH (default 1000x520)")
    ap.add_argument("--check", default="", help="expression on the top block `tb` that must hold at the screenshot")
    ap.add_argument("--cycles", type=int, default=1,
                    help="runs in this process: K - 1 stress cycles, then the screenshot run (default 1)")
    ap.add_argument("--cycle-seconds", type=float, default=1.5, help="length of a stress cycle (default 1.5 s)")
    ap.add_argument("--cycle-check", default="", help="expression on `tb` that must hold at the end of each stress cycle")
    ap.add_argument("--cycle-speed", type=float, default=1.0,
                    help="stress cycles run every Throttle of the flowgraph this many times faster (default 1)")
    args = ap.parse_args()
    try:
        width, height = (int(v) for v in args.size.lower().split("x"))
        if width < 1 or height < 1:
            raise ValueError
    except ValueError:
        fail(f"--size must be WxH in pixels, got {args.size!r}")
    if args.cycles < 1:
        fail(f"--cycles must be at least 1, got {args.cycles}")

    module, script_id = compile_flowgraph(args.grc, args.outdir, args.compiled)
    from PyQt5 import Qt, QtCore

    app = Qt.QApplication([script_id])
    started = time.monotonic()
    for cycle in range(1, args.cycles):
        tb = start(module, script_id, width, height)
        for block in vars(tb).values():
            if type(block).__name__ == "throttle":
                block.set_sample_rate(block.sample_rate() * args.cycle_speed)
        painter = QtCore.QTimer()
        painter.timeout.connect(tb.repaint)
        painter.start(0)
        QtCore.QTimer.singleShot(int(args.cycle_seconds * 1000), app.quit)
        app.exec_()
        # A slow machine (a sanitizer build) may take longer to answer its first frames: the
        # cycle goes on until its check holds, up to CYCLE_GRACE_S more.
        give_up = time.monotonic() + CYCLE_GRACE_S
        while not holds(args.cycle_check, tb, quiet=True) and time.monotonic() < give_up:
            app.processEvents(QtCore.QEventLoop.AllEvents, 50)
        painter.stop()
        ok = holds(args.cycle_check, tb)
        tear_down(module, tb, app)  # also on failure: exiting with the flowgraph running crashes
        del tb
        if not ok:
            fail(f"stress cycle {cycle}: after {args.cycle_seconds + CYCLE_GRACE_S:g} s this is false: "
                 f"{args.cycle_check}")
    if args.cycles > 1:
        print(f"screenshot_qt: {args.cycles - 1} stress cycles of {args.cycle_seconds:g} s "
              f"in {time.monotonic() - started:.1f} s")

    tb = start(module, script_id, width, height)

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
        elif not holds(args.check, tb):
            print(f"screenshot_qt: saved {args.png}, but at {args.seconds:g} s this is false: {args.check}",
                  file=sys.stderr)
            app.exit(1)
        else:
            print(f"screenshot_qt: saved {args.png} ({image.width()}x{image.height()}, {len(colours)} colours)")
            app.exit(0)

    QtCore.QTimer.singleShot(int(args.seconds * 1000), shoot)
    rc = app.exec_()
    tear_down(module, tb, app)
    del tb, shoot
    sys.exit(rc)


if __name__ == "__main__":
    main()
