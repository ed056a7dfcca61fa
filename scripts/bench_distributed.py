#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scaling of distributed training on this machine (a benchmark, not a test).

  bench_distributed.py BUILD/apps/sems_train [--repeat 3] [--frames 6000] [--epochs 2] [--world 2]

Alternates, `repeat` times, one rank x 1 thread and `world` ranks x 1 thread (FileStore on
127.0.0.1) on the same learned-mask classification workload (global batch 256, same seed)
and reads from each bundle.json the training frames/s of every epoch (all ranks together)
and the gradient all-reduce time per step. The anchor is the single rank measured in the
same run: the speed-up is a ratio of rows of one run, because the machine may be shared.
A third row is the machine's own ceiling: `world` independent single-rank trainings at once,
each on its share (frames / world, batch 256 / world, no communication), their frames/s
summed; distributed training cannot beat it. Prints a Markdown table for
docs/reference/distributed_training.md.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time


def run(exe, args, world, tmp, tag, independent=False):
    """One training of `world` ranks, or (independent) `world` single-rank trainings at once,
    each given args_share(args, world)."""
    out = os.path.join(tmp, tag)
    store = os.path.join(tmp, tag + "_store")
    procs = []
    t0 = time.time()
    for r in range(world):
        if independent:
            dist, rank_args = [], args_share(args, world)
        else:
            dist = [] if world == 1 else ["--world-size", str(world), "--rank", str(r), "--store-file", store,
                                          "--dist-timeout", "600"]
            rank_args = args
        procs.append(subprocess.Popen(["nice", exe] + rank_args + dist + ["--out", out if r == 0 else out + "_%d" % r],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True))
    cpu = []
    for p in procs:  # CPU seconds (user + system) of each rank, from the kernel's accounting
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        if p.returncode != 0:
            sys.exit("%s failed: %s" % (tag, p.stderr.read()))
        cpu.append(ru.ru_utime + ru.ru_stime)
    wall = time.time() - t0
    with open(os.path.join(out, "bundle.json")) as f:
        t = json.load(f)["training"]
    fps = [h["train_frames_per_s"] for h in t["history"]]
    if independent:  # the trainings' frames/s summed, epoch by epoch
        for r in range(1, world):
            with open(os.path.join(out + "_%d" % r, "bundle.json")) as f:
                other = [h["train_frames_per_s"] for h in json.load(f)["training"]["history"]]
            fps = [a + b for a, b in zip(fps, other)]
    ms = t.get("distributed", {}).get("gradient_allreduce_ms_per_step", 0.0)
    return {"fps_mean": statistics.mean(fps), "fps_best": max(fps), "allreduce_ms": ms, "wall": wall,
            "cpu_max": max(cpu), "cpu_sum": sum(cpu),
            "floats": t.get("distributed", {}).get("gradient_floats_per_step", 0)}


def args_share(args, world):
    """The arguments of one of `world` independent trainings: frames and batch divided."""
    a = list(args)
    for flag in ("--frames", "--batch"):
        i = a.index(flag)
        a[i + 1] = str(int(a[i + 1]) // world)
    return a


# The exchange alone, ranks in lockstep (no waiting for a slower rank): the same c10d
# ProcessGroupGloo through python3-torch, Gloo on the loopback interface only.
LOCKSTEP = r"""
import sys, time, torch, torch.distributed as dist
torch.set_num_threads(1)
rank, world, path, n = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
dist.init_process_group("gloo", init_method="file://" + path, rank=rank, world_size=world)
t = torch.randn(n)
for _ in range(20):
    dist.all_reduce(t)
times = []
for _ in range(200):
    dist.barrier()
    t0 = time.perf_counter()
    dist.all_reduce(t)
    times.append(time.perf_counter() - t0)
times.sort()
if rank == 0:
    print("%.3f %.3f" % (1e3 * times[len(times) // 2], 1e3 * times[0]))
"""


def lockstep(world, floats, tmp):
    env = dict(os.environ, GLOO_SOCKET_IFNAME="lo")
    path = os.path.join(tmp, "lockstep_store")
    procs = [subprocess.Popen([sys.executable, "-c", LOCKSTEP, str(r), str(world), path, str(floats)], env=env,
                              stdout=subprocess.PIPE, text=True) for r in range(world)]
    out = [p.communicate()[0] for p in procs]
    med, best = map(float, out[0].split())
    return med, best


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sems_train")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--frames", type=int, default=6000)
    ap.add_argument("--epochs", type=int, default=2)
    ap.add_argument("--world", type=int, default=2)
    a = ap.parse_args()
    args = ["--task", "classify", "--snr-min", "0", "--snr-max", "20", "--frames", str(a.frames),
            "--epochs", str(a.epochs), "--decoder-epochs", "0", "--batch", "256", "--threads", "1",
            "--seed", "1", "--eval-snr", "10", "--eval-frames", "100", "--quiet"]
    tmp = tempfile.mkdtemp(prefix="sems_bench_dist_")
    rows = []
    for i in range(a.repeat):
        kinds = [(1, False), (a.world, False), (a.world, True)]
        for world, independent in kinds if i % 2 == 0 else kinds[::-1]:
            r = run(a.sems_train, args, world, tmp, "w%d%s_r%d" % (world, "i" if independent else "", i), independent)
            r.update(world=world, repeat=i, independent=independent)
            rows.append(r)
            print("repeat %d, %d %s: %.0f frames/s (epoch mean), best epoch %.0f, all-reduce %.2f ms/step, "
                  "%.1f s wall, CPU s per rank max %.1f / sum %.1f"
                  % (i, world, "independent trainings" if independent else "rank(s)", r["fps_mean"], r["fps_best"], r["allreduce_ms"], r["wall"], r["cpu_max"], r["cpu_sum"]),
                  flush=True)
    one = [r for r in rows if r["world"] == 1]
    many = [r for r in rows if r["world"] == a.world and not r["independent"]]
    alone = [r for r in rows if r["independent"]]
    print()
    print("| ranks x threads | training frames/s (best of %d runs, epoch mean) | median | speed-up (best / median) "
          "| gradient all-reduce ms/step (median) |" % a.repeat)
    print("|---|---|---|---|---|")
    b1 = max(r["fps_mean"] for r in one)
    m1 = statistics.median(r["fps_mean"] for r in one)
    for label, rs in (("1 x 1", one), ("%d x 1" % a.world, many),
                      ("%d independent x 1 (ceiling)" % a.world, alone)):
        b = max(r["fps_mean"] for r in rs)
        m = statistics.median(r["fps_mean"] for r in rs)
        ms = statistics.median(r["allreduce_ms"] for r in rs)
        print("| %s | %.0f | %.0f | %.2fx / %.2fx | %s |" % (label, b, m, b / b1, m / m1,
                                                        "%.2f (%d floats)" % (ms, rs[0]["floats"]) if rs is many else "-"))
    # Per repeat: the ratio of the two runs made back to back.
    ratios = [m["fps_mean"] / o["fps_mean"] for o, m in zip(one, many)]
    print("\nback-to-back ratios (%d ranks / 1 rank): %s" % (a.world, ", ".join("%.2f" % x for x in ratios)))
    ceiling = [c["fps_mean"] / o["fps_mean"] for o, c in zip(one, alone)]
    print("back-to-back ratios (%d independent trainings / 1 rank): %s" % (a.world, ", ".join("%.2f" % x for x in ceiling)))
    # What the ranks' CPU work says about free cores: the run takes as long as its busiest
    # rank, so the speed-up on idle cores is bounded by CPU(1 rank) / max CPU(one of the ranks).
    c1 = statistics.median(r["cpu_max"] for r in one)
    cm = statistics.median(r["cpu_max"] for r in many)
    cs = statistics.median(r["cpu_sum"] for r in many)
    print("CPU seconds (median): 1 rank %.1f; %d ranks: busiest rank %.1f, all ranks %.1f -> speed-up on idle cores "
          "<= %.2fx, CPU overhead of distribution %+.0f%%" % (c1, a.world, cm, cs, c1 / cm, 100 * (cs / c1 - 1)))
    floats = many[0]["floats"]
    med, best = lockstep(a.world, floats, tmp)
    print("all-reduce of the %d-float gradient bucket alone, %d ranks in lockstep on loopback: median %.3f ms, "
          "best %.3f ms (200 calls)" % (floats, a.world, med, best))
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
