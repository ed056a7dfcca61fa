#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""CTest driver: sems_train as two ranks on 127.0.0.1 (FileStore in a temporary directory).

  check_distributed_training.py SEMS_TRAIN equivalence   two ranks with global batch B against
        one rank with batch B and the same seed: both beat chance and their test accuracies
        agree within 3 standard errors (statistical: each rank draws its own frames, noise
        and Gumbel samples); the bundle records world size and per-rank batch; rank 1
        writes nothing; a 2-rank delay run completes (delay grid and error gather).
  check_distributed_training.py SEMS_TRAIN failure       a missing rank fails the rendezvous,
        a killed rank (SIGKILL) or a stopped one (SIGSTOP) makes rank 0 exit non-zero
        within the timeout, with an error naming the failed operation.
  check_distributed_training.py SEMS_TRAIN unavailable   (built without Gloo) --world-size 2
        says why.

The exact part of data parallelism (all-reduced half-batch gradients equal the full
batch's) is tested in lib/learning/distributed/qa_learning_distributed.cc.
"""
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

TINY = ["--task", "classify", "--classes", "pedestrian,car", "--snr", "20", "--frames", "1600",
        "--epochs", "3", "--decoder-epochs", "2", "--batch", "64", "--pilots", "16",
        "--threads", "1", "--seed", "7", "--eval-snr", "20"]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def launch(exe, args, out, log):
    return subprocess.Popen([exe] + args + ["--out", out], stdout=open(log, "w"), stderr=subprocess.STDOUT)


def ranks(exe, args, tmp, out, world=2, timeout=60, tag="run"):
    store = os.path.join(tmp, tag + "_store")
    procs = []
    for r in range(world):
        dist = ["--world-size", str(world), "--rank", str(r), "--store-file", store,
                "--dist-timeout", str(timeout)]
        # Only rank 0 may write: give the others their own --out and check it stays absent.
        o = out if r == 0 else out + "_rank%d" % r
        procs.append(launch(exe, args + dist, o, os.path.join(tmp, "%s_rank%d.log" % (tag, r))))
    codes = [p.wait(timeout=600) for p in procs]
    for r, c in enumerate(codes):
        if c != 0:
            fail("%s rank %d exited %d:\n%s" % (tag, r, c, open(os.path.join(tmp, "%s_rank%d.log" % (tag, r))).read()))
        if r > 0 and os.path.exists(out + "_rank%d" % r):
            fail("rank %d wrote a bundle (only rank 0 may)" % r)


def bundle(d):
    with open(os.path.join(d, "bundle.json")) as f:
        return json.load(f)


def mask_cells(d):
    b = bundle(d)
    with open(os.path.join(d, b.get("mask_file", "mask.json"))) as f:
        m = json.load(f)
    return {(p[0], p[1]) if isinstance(p, list) else (p["symbol"], p["subcarrier"]) for p in m["pilots"]}


def equivalence(exe):
    tmp = tempfile.mkdtemp(prefix="sems_dist_eq_")
    one, two = os.path.join(tmp, "one"), os.path.join(tmp, "two")
    t0 = time.time()
    p = launch(exe, TINY, one, os.path.join(tmp, "one.log"))
    if p.wait(timeout=600) != 0:
        fail("single rank:\n" + open(os.path.join(tmp, "one.log")).read())
    ranks(exe, TINY, tmp, two, tag="two")
    b1, b2 = bundle(one), bundle(two)
    t1, t2 = b1["training"], b2["training"]
    if (t1["world_size"], t1["batch_per_rank"]) != (1, 64):
        fail("single rank records world %s, batch per rank %s" % (t1["world_size"], t1["batch_per_rank"]))
    if (t2["world_size"], t2["batch"], t2["batch_per_rank"]) != (2, 64, 32):
        fail("two ranks record world %s, batch %s, batch per rank %s" % (t2["world_size"], t2["batch"], t2["batch_per_rank"]))
    if not t2["distributed"]["gradient_allreduce_ms_per_step"] > 0:
        fail("no all-reduce time recorded")
    a1, a2 = b1["metrics"]["test"]["accuracy"], b2["metrics"]["test"]["accuracy"]
    n1, n2 = b1["metrics"]["test"]["frames"], b2["metrics"]["test"]["frames"]
    if n1 != 160 or n2 != 160:
        fail("test frames %d (one rank) and %d (two ranks, summed over ranks), expected 160 each" % (n1, n2))
    # Two independent estimates of one accuracy: their difference has variance
    # p(1-p)(1/n1 + 1/n2); p at least one frame away from 0 and 1.
    p = min(max((a1 + a2) / 2, 1.0 / n1), 1 - 1.0 / n1)
    se = math.sqrt(p * (1 - p) * (1.0 / n1 + 1.0 / n2))
    common = len(mask_cells(one) & mask_cells(two))
    print("one rank: test accuracy %.4f; two ranks: %.4f; |diff| %.4f, 3 SE %.4f; learned masks share %d of 16 pilots"
          % (a1, a2, abs(a1 - a2), 3 * se, common))
    print("all-reduce %.2f ms/step over %d floats"
          % (t2["distributed"]["gradient_allreduce_ms_per_step"], t2["distributed"]["gradient_floats_per_step"]))
    if min(a1, a2) < 0.75:
        fail("a run did not learn (chance is 0.5): %.3f, %.3f" % (a1, a2))
    if abs(a1 - a2) > 3 * se:
        fail("accuracies differ by more than 3 standard errors")
    # Delay: the dictionary grid from all ranks' delays (same network on both ranks) and
    # the median/RMSE over all ranks' errors.
    delay = ["--task", "delay", "--snr", "20", "--frames", "400", "--epochs", "1", "--decoder-epochs", "1",
             "--batch", "32", "--pilots", "16", "--threads", "1", "--seed", "3", "--eval-snr", "20", "--quiet"]
    dl = os.path.join(tmp, "delay")
    ranks(exe, delay, tmp, dl, tag="delay")
    m = bundle(dl)["metrics"]["test"]
    if m["frames"] != 40 or not (m["median_abs_error_index"] >= 0 and m["rmse_index"] >= m["mae_index"] * 0.999):
        fail("delay metrics over two ranks: %s" % m)
    print("delay over two ranks: %s" % m)
    print("PASS (%.1f s)" % (time.time() - t0))
    shutil.rmtree(tmp)


def wait_exit(p, limit):
    t = time.time()
    try:
        code = p.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()
        fail("rank 0 still running %.0f s after its peer failed (a hang)" % limit)
    return code, time.time() - t


def failure(exe):
    tmp = tempfile.mkdtemp(prefix="sems_dist_fail_")
    long_run = [a if a != "3" else "50" for a in TINY]  # --epochs 50: still training when killed
    slack = 15.0  # LibTorch start-up on a loaded machine
    # 1. Rank 1 never starts: the rendezvous fails after the timeout.
    log = os.path.join(tmp, "alone.log")
    p = launch(exe, TINY + ["--world-size", "2", "--rank", "0", "--store-file", os.path.join(tmp, "alone_store"),
                            "--dist-timeout", "3"], os.path.join(tmp, "alone"), log)
    code, s = wait_exit(p, 3 + slack + 30)
    text = open(log).read()
    if code == 0 or "rendezvous at FileStore" not in text or "timeout 3 s" not in text:
        fail("missing rank: exit %d after %.1f s:\n%s" % (code, s, text))
    print("missing rank: exit %d after %.1f s (timeout 3 s): %s" % (code, s, text.strip().splitlines()[-1]))
    # 2. and 3. Rank 1 is killed / stopped once rank 0 reports its first epoch.
    for how, sig, timeout in (("killed", signal.SIGKILL, 30), ("stopped", signal.SIGSTOP, 4)):
        store = os.path.join(tmp, how + "_store")
        dist = lambda r: ["--world-size", "2", "--rank", str(r), "--store-file", store, "--dist-timeout", str(timeout)]
        log0, log1 = os.path.join(tmp, how + "_rank0.log"), os.path.join(tmp, how + "_rank1.log")
        p1 = launch(exe, long_run + dist(1), os.path.join(tmp, how + "_1"), log1)
        p0 = launch(exe, long_run + dist(0), os.path.join(tmp, how + "_0"), log0)
        deadline = time.time() + 300
        while "epoch" not in open(log0).read():
            if p0.poll() is not None or time.time() > deadline:
                p1.kill()
                fail("%s: rank 0 never trained:\n%s" % (how, open(log0).read()))
            time.sleep(0.2)
        os.kill(p1.pid, sig)
        code, s = wait_exit(p0, timeout + slack)
        os.kill(p1.pid, signal.SIGKILL)
        p1.wait()
        text = open(log0).read()
        if code == 0 or "failed" not in text:
            fail("%s rank: rank 0 exit %d after %.1f s:\n%s" % (how, code, s, text))
        if s > timeout + 5:
            fail("%s rank: rank 0 took %.1f s to stop (timeout %d s)" % (how, s, timeout))
        print("%s rank: rank 0 exit %d after %.1f s (timeout %d s): %s"
              % (how, code, s, timeout, text.strip().splitlines()[-1]))
    print("PASS")
    shutil.rmtree(tmp)


def unavailable(exe):
    r = subprocess.run([exe] + TINY + ["--out", tempfile.mkdtemp(), "--world-size", "2", "--rank", "0",
                                       "--store-file", "/nonexistent/store"], capture_output=True, text=True)
    if r.returncode == 0 or "libgloo-dev" not in r.stderr:
        fail("--world-size 2 without Gloo: exit %d, %s" % (r.returncode, r.stderr))
    print(r.stderr.strip())
    print("PASS")


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[2] not in ("equivalence", "failure", "unavailable"):
        sys.exit(__doc__)
    {"equivalence": equivalence, "failure": failure, "unavailable": unavailable}[sys.argv[2]](sys.argv[1])
