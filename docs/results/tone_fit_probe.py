#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Which slow-time features tell a car from a pedestrian in the `any` heading scene.

One subcarrier of noiseless (and 30 dB) frames of the project's channel model (the random scene
with heading `any`, one path): a small MLP (the same for every feature set, 30 epochs of Adam
on 24 000 frames, scored on 3 000 others) on
  - the 64-bin log power profile (what the spectral classifier's convolutions see),
  - the lag products y[n+1] y*[n] (phase structure, invariant to the gain's phase),
  - the tone/chirp-fit shares log(1 - E_j + 1e-4) of 9 rates over +-2 bins (the decoder's fit,
    searched on a 512-bin grid here),
  - profile and shares together;
and, noiseless, the nearest of 24 000 / 120 000 stored frames (|<y, y_ref>| / norms).
docs/RESULTS.md, "The tone/chirp fit":

    PYTHONPATH=build/python_pkg OMP_NUM_THREADS=1 /usr/bin/python3 docs/results/tone_fit_probe.py
"""
import json

import numpy as np
import torch

from gnuradio import sems
from gnuradio.sems.datasets import channel_batches

N = 32


def draw(scene, n, seed):
    ys, cs = [], []
    for h, t in channel_batches(scene, 2000, -(-n // 2000), seed=seed):
        ys.append(np.asarray(h)[:, :, 0])
        cs += [x["class"] for x in t]
    return np.concatenate(ys)[:n], np.array(cs)[:n]


def noisy(y, snr, rng):
    if snr is None:
        return y
    s = 10 ** (-snr / 10)
    return y + np.sqrt(s / 2) * (rng.standard_normal(y.shape) + 1j * rng.standard_normal(y.shape))


def profile(y):
    y = y / np.sqrt((np.abs(y) ** 2).mean(1, keepdims=True) + 1e-30)
    p = np.abs(np.fft.fft(y, 64, axis=1)) ** 2
    return np.log(p / p.mean(1, keepdims=True) + 1e-3)


def lags(y):
    l1 = y[:, 1:] * np.conj(y[:, :-1])
    l1 = l1 / (np.abs(l1).mean(1, keepdims=True) + 1e-30)
    return np.concatenate([l1.real, l1.imag], 1)


def tone_fit(y, rates=9, sweep=2.0, grid=512):
    n = np.arange(N)
    c = n - (N - 1) / 2
    f = np.exp(-2j * np.pi * np.outer(np.arange(grid), n) / grid)
    total = (np.abs(y) ** 2).sum(1) * N + 1e-30
    out = []
    # the decoder's rates (classifier_settings::chirp_rates)
    for a in sems.classifier_chirp_rates(json.dumps({"chirp_bins": rates, "chirp_sweep_bins": sweep}), N):
        e = (np.abs((y * np.exp(-1j * np.pi * a * c ** 2)) @ f.T) ** 2).max(1) / total
        out.append(np.log(1 - e + 1e-4))
    return np.stack(out, 1)


def mlp_accuracy(xtr, ytr, xte, yte, seed=0, epochs=30):
    torch.manual_seed(seed)
    xtr, xte = torch.tensor(xtr, dtype=torch.float32), torch.tensor(xte, dtype=torch.float32)
    mu, sd = xtr.mean(0), xtr.std(0) + 1e-6
    xtr, xte = (xtr - mu) / sd, (xte - mu) / sd
    net = torch.nn.Sequential(torch.nn.Linear(xtr.shape[1], 128), torch.nn.LeakyReLU(0.1),
                              torch.nn.Linear(128, 64), torch.nn.LeakyReLU(0.1), torch.nn.Linear(64, 3))
    opt = torch.optim.Adam(net.parameters(), 3e-3)
    t = torch.tensor(ytr)
    for _ in range(epochs):
        perm = torch.randperm(len(t))
        for i in range(0, len(t), 256):
            b = perm[i:i + 256]
            opt.zero_grad()
            torch.nn.functional.cross_entropy(net(xtr[b]), t[b]).backward()
            opt.step()
    with torch.no_grad():
        return float((net(xte).argmax(1).numpy() == yte).mean())


def main():
    torch.set_num_threads(1)
    spec = sems.random_spec()
    spec.heading = sems.heading_from_name("any")
    scene = sems.scene.random(spec)
    ytr, ctr = draw(scene, 120000, 11)
    yte, cte = draw(scene, 3000, 12)
    print("any heading, one path, one subcarrier: 24 000 training frames, 3 000 test frames")
    rng = np.random.default_rng(0)
    for snr in (None, 30.0):
        a, b = noisy(ytr[:24000], snr, rng), noisy(yte, snr, rng)
        label = "noiseless" if snr is None else "%g dB" % snr
        pa, pb, ta, tb = profile(a), profile(b), tone_fit(a), tone_fit(b)
        for name, xa, xb in (("log power profile (64 bins)", pa, pb), ("lag products y[n+1] y*[n]", lags(a), lags(b)),
                             ("tone/chirp-fit shares (9 rates)", ta, tb),
                             ("profile + shares", np.concatenate([pa, ta], 1), np.concatenate([pb, tb], 1))):
            print("%-10s MLP on %-32s accuracy %.4f" % (label, name, mlp_accuracy(xa, ctr[:24000], xb, cte)), flush=True)
    unit = lambda y: y / np.linalg.norm(y, axis=1, keepdims=True)
    ref, test = unit(ytr), unit(yte)
    for n in (24000, 120000):
        pred = ctr[:n][np.abs(test @ ref[:n].conj().T).argmax(1)]
        print("noiseless  nearest of %6d stored frames             accuracy %.4f" % (n, (pred == cte).mean()))


if __name__ == "__main__":
    main()
