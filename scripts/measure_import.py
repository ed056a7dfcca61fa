#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Wall time and resident memory of `import gnuradio.sems` (no learning name used).

Each figure is the median over --runs fresh interpreters per build tree; the runs of the
build trees are interleaved, so a busy machine slows them alike. Reports VmRSS and VmHWM
from /proc/self/status right after the import, and whether LibTorch got mapped.

Usage: /usr/bin/python3 scripts/measure_import.py BUILD_DIR [BUILD_DIR ...] [--runs 5]
(each BUILD_DIR holds python_pkg/ and lib/, as a CMake build tree of gr-sems does)
"""
import argparse
import os
import statistics
import subprocess
import sys

CHILD = r"""
import time
t = time.perf_counter()
import gnuradio.sems
dt = time.perf_counter() - t
st = {l.split(":")[0]: int(l.split()[1]) for l in open("/proc/self/status") if l.startswith(("VmRSS", "VmHWM"))}
torch = any("libtorch" in l for l in open("/proc/self/maps"))
print(dt, st["VmRSS"], st["VmHWM"], int(torch))
"""


def one(build):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(build, "python_pkg")
    env["LD_LIBRARY_PATH"] = os.path.join(build, "lib")
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, check=True, capture_output=True, text=True)
    dt, rss, hwm, torch = out.stdout.split()
    return float(dt), int(rss), int(hwm), bool(int(torch))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("builds", nargs="+")
    ap.add_argument("--runs", type=int, default=5)
    a = ap.parse_args()
    samples = {b: [] for b in a.builds}
    for _ in range(a.runs):
        for b in a.builds:
            samples[b].append(one(b))
    print("%-40s %10s %12s %12s %8s" % ("build", "import s", "VmRSS MiB", "VmHWM MiB", "libtorch"))
    for b, s in samples.items():
        med = lambda i: statistics.median(x[i] for x in s)  # noqa: E731
        print("%-40s %10.3f %12.1f %12.1f %8s" % (b, med(0), med(1) / 1024, med(2) / 1024,
                                                  "yes" if all(x[3] for x in s) else
                                                  ("no" if not any(x[3] for x in s) else "mixed")))
        print("  runs (s):", " ".join("%.3f" % x[0] for x in s))


if __name__ == "__main__":
    main()
