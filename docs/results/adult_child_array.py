#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Adults against children over a track, from one antenna and from an 8-element array.

    /usr/bin/python3 docs/results/adult_child_array.py draw  --dir DIR   # the tracks (about an hour on one core)
    /usr/bin/python3 docs/results/adult_child_array.py train --dir DIR   # 4 decoders x 3 seeds (about 30 min on 1 core)
    /usr/bin/python3 docs/results/adult_child_array.py table [--dir DIR]  # the table from the kept results

(run with PYTHONPATH and LD_LIBRARY_PATH at a build tree, or an installed gr-sems). The tracks:
walking adults and children of the kinematic class library, any heading, seen by the 8-element
half-wavelength ULA `ula8_3g` on the paper's frame from an azimuth in [-0.8, 0.8] rad, moving
straight in the ground plane (`"motion": "straight"`) over up to 64 frames (2.05 s; a track ends
early when the walker leaves its range or the azimuth interval), a Rayleigh gain new every frame. Per frame and element the pilots are 32 symbols of subcarrier 1 (Doppler) and 32
subcarriers of symbol 0 (delay), with CN(0, sigma^2) noise at 20 dB per pilot and element.
Training tracks 0..7999 of seed 1 (the first 1000 for validation, the epoch kept is the best on
them), test tracks 0..999 of seed 2 with one noise draw shared by every decoder.

Each frame gives a decoder its slow time's normalized autocorrelation at lags 1..31 (the
Doppler spectrum's shape, free of the frame's gain), and the decoder is one temporal CNN over the
track's frames and a small MLP head that also takes three kinematic inputs (zeros where a
decoder has none); four inputs, the same network and budget (30 epochs of Adam
at 1e-3, batch 64) for each, three training seeds each:
- one: element 0's Doppler pilots alone (one antenna);
- beam: the array's Doppler pilots beamformed towards the frame's azimuth, found as the peak of
  the beamforming spectrum of both pilot sets (a 961-point grid on [-1.2, 1.2] rad and a
  parabola through the peak);
- beam_kin: beam, and the track's speed and heading from the array (track_kinematics): each
  frame's position from that azimuth and the range of the beamformed delay pilots' profile peak,
  a robust straight line through them, and the Doppler's radial velocity;
- beam_oracle: beam, and the true speed and heading (what a perfect track would give).
The table gives each test accuracy (mean over seeds, and each seed), and paired differences
over the same test tracks with a bootstrap of the tracks (10 000 resamples) and Holm's
correction over the comparisons.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "apps", "figures"))
from paired_stats import holm  # noqa: E402  (the project's Holm correction)

SCENE = ('{"format": "sems.scene", "version": 1, "classes": "kinematic", "array": "ula8_3g", '
         '"random": {"classes": ["adult", "child"], "heading": "any", "azimuth_rad": [-0.8, 0.8], '
         '"tracks": {"frames": 64, "motion": "straight"}}}')
K = 64                      # frames per track
SNR_DB = 20.0               # per pilot and element
SETS = {"train": (1, 0, 8000), "test": (2, 0, 1000)}  # seed, first track, tracks
CONFIGS = ["one", "beam", "beam_kin", "beam_oracle"]
SEEDS = [0, 1, 2]
N_VAL = 1000
NOISE_SEED = {"train": 11, "test": 7}
C = 299792458.0


def draw(sems, name, out):
    seed, first, count = SETS[name]
    sc = sems.scene.parse(SCENE)
    cm = sems.channel_model(sems.frame_of("paper"), sc, seed)
    E = cm.n_elements()
    D = np.zeros((count, K, E, 32), np.complex64)
    R = np.zeros((count, K, E, 32), np.complex64)
    L = np.zeros(count, int)
    y = np.zeros(count, int)
    kin = np.zeros((count, 2))
    truth = np.zeros((count, K, 3))
    t0 = time.time()
    for i in range(count):
        L[i] = cm.begin_track(first + i)
        for f in range(L[i]):
            r = cm.draw(f)
            t = r.truth
            if f == 0:
                y[i] = 0 if t[sems.keys.class_name] == "adult" else 1
                b = r.bodies[r.truth_body]
                kin[i] = (b.speed_mps, b.heading_rad)
            truth[i, f] = (t[sems.keys.range_m], t[sems.keys.azimuth_rad], t[sems.keys.velocity_mps])
            for e in range(E):
                h = cm.channel(r, 0, e)
                D[i, f, e] = h[:, 1]
                R[i, f, e] = h[0, :32]
        if (i + 1) % 200 == 0:
            print(f"{name}: {i + 1}/{count} tracks, {time.time() - t0:.0f} s", flush=True)
    np.savez(out, D=D, R=R, L=L, y=y, kin=kin, truth=truth)


def acf(y):
    """(..., 32) slow time -> (..., 62): the normalized autocorrelation at lags 1..31."""
    p = (np.abs(y) ** 2).sum(-1)
    r = np.stack([(y[..., k:] * np.conj(y[..., :-k])).sum(-1) for k in range(1, 32)], -1) / p[..., None]
    return np.concatenate([r.real, r.imag], -1).astype(np.float32)


def track_kinematics(az, rng_m, radial, power, L, t):
    """(speed, cos θ, |sin θ|) of each track from its frames' azimuths, ranges, mean radial
    velocities and powers: a straight line fitted to the positions, weighted by the frames' power
    and refitted without the frames whose residual exceeds the median residual by more than three
    robust deviations (a fade or a limb can move a frame's peak), its velocity's cross-range part
    with the power-weighted mean of the Doppler's radial velocity (far finer than the range's); θ
    against the line of sight at the track's start. A track of one frame gives 0 for all three."""
    n = len(L)
    kin = np.zeros((n, 3), np.float32)
    for i in range(n):
        k = L[i]
        if k < 2:
            continue
        px, py = rng_m[i, :k] * np.cos(az[i, :k]), rng_m[i, :k] * np.sin(az[i, :k])
        w = power[i, :k] / power[i, :k].mean()
        keep = np.ones(k, bool)
        for _ in range(3):
            M = np.stack([np.ones(k), t[:k]], 1) * np.sqrt(w * keep)[:, None]
            (x0, vx), (y0, vy) = (np.linalg.lstsq(M, q * np.sqrt(w * keep), rcond=None)[0] for q in (px, py))
            res = np.hypot(px - x0 - vx * t[:k], py - y0 - vy * t[:k])
            mad = 1.4826 * np.median(np.abs(res[keep] - np.median(res[keep])))
            keep = res <= np.median(res[keep]) + 3 * max(mad, 1e-3)
            if keep.sum() < 2:
                keep[:] = True
        mid = 0.5 * (t[0] + t[k - 1])
        mx, my = x0 + vx * mid, y0 + vy * mid
        los = np.array([mx, my]) / np.hypot(mx, my)
        across = -los[1] * vx + los[0] * vy  # the velocity's part towards increasing azimuth at mid-track
        towards = np.average(radial[i, :k], weights=w)  # approaching, at mid-track on average
        s = np.hypot(towards, across)
        # the heading against the start's line of sight: the velocity at mid-track turned back there
        vel = towards * (-los) + across * np.array([-los[1], los[0]])
        r0 = np.hypot(x0, y0)
        kin[i] = (s, -(x0 * vel[0] + y0 * vel[1]) / (r0 * s), abs(x0 * vel[1] - y0 * vel[0]) / (r0 * s))
    return kin


def frame_features(sems, Y, Z, A, grid, arr):
    """One chunk of tracks' noisy pilots (n x K x E x 32 each) -> per frame: element 0's and the
    beamformed autocorrelation, the azimuth, the range, the mean radial velocity and the power."""
    fs = sems.frame_of("paper")
    lam, df, T = C / fs.carrier_hz, fs.bandwidth_hz / fs.n_subcarriers, fs.symbol_interval_s
    n, _, E, _ = Y.shape
    X = np.concatenate([Y, Z], 3)
    cov = np.einsum("nkep,nkfp->nkef", X, X.conj())  # the pilots' spatial covariance per frame
    P = ((cov.reshape(-1, E) @ A.T).reshape(n, K, E, len(grid)) * A.conj().T).sum(2).real  # a^H C a
    g = P.argmax(-1).clip(1, len(grid) - 2)
    p0, p1, p2 = [np.take_along_axis(P, (g + o)[..., None], -1)[..., 0] for o in (-1, 0, 1)]
    az = grid[g] + 0.5 * (p0 - p2) / (p0 - 2 * p1 + p2) * (grid[1] - grid[0])
    steer = np.array([[sems.steering_vector(arr, a, 0.0, lam) for a in row] for row in az])

    def beamformed(x):
        return np.einsum("nke,nkep->nkp", steer.conj(), x) / E

    profile = np.abs(np.fft.ifft(beamformed(Z), 2048, axis=-1)) ** 2
    b = beamformed(Y)
    lag1 = (b[..., 1:] * np.conj(b[..., :-1])).sum(-1)
    return dict(one=acf(Y[:, :, 0]), beam=acf(b), az=az,
                range=C * (profile.argmax(-1) / (2048 * df)) / 2,
                radial=np.angle(lag1) / (2 * np.pi * T) * lam / 2,  # the mean Doppler as a velocity, + = approaching
                power=(np.abs(b) ** 2).sum(-1))


def features(sems, pilots, noise_seed, chunk=250):
    fs = sems.frame_of("paper")
    lam = C / fs.carrier_hz
    arr = sems.array_geometry.find("ula8_3g")
    grid = np.linspace(-1.2, 1.2, 961)
    A = np.array([sems.steering_vector(arr, g, 0.0, lam) for g in grid])
    d = np.load(pilots)
    D, R, L = d["D"], d["R"], d["L"]
    rng = np.random.default_rng(noise_seed)
    sigma = np.sqrt(10 ** (-SNR_DB / 10) / 2)

    def noisy(x):
        return x + sigma * (rng.standard_normal(x.shape) + 1j * rng.standard_normal(x.shape))

    parts = [frame_features(sems, noisy(D[c:c + chunk]), noisy(R[c:c + chunk]), A, grid, arr)
             for c in range(0, len(L), chunk)]  # chunks: memory, and the same noise for any chunk's reader
    f = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    kin = track_kinematics(f["az"], f["range"], f["radial"], f["power"], L, np.arange(K) * fs.n_symbols * fs.symbol_interval_s)
    s, th = d["kin"][:, 0], d["kin"][:, 1]
    return dict(one=f["one"], beam=f["beam"], kin=kin,
                kin_true=np.stack([s, np.cos(th), np.abs(np.sin(th))], 1).astype(np.float32),
                valid=(np.arange(K)[None, :] < L[:, None]).astype(np.float32), y=d["y"], az=f["az"],
                range=f["range"], truth=d["truth"])


def train_one(feat_train, feat_test, config, seed, epochs=30):
    import torch
    import torch.nn as nn
    torch.set_num_threads(1)
    torch.manual_seed(seed)
    rng = np.random.default_rng(100 + seed)

    def tensors(d):
        x = d["one"] if config == "one" else d["beam"]
        z = {"beam_kin": d["kin"], "beam_oracle": d["kin_true"]}.get(config, np.zeros((len(x), 3), np.float32))
        return (torch.tensor(x.transpose(0, 2, 1)), torch.tensor(d["valid"]), torch.tensor(z),
                torch.tensor(d["y"]))

    Str, Vtr, Ztr, ytr = tensors(feat_train)
    Ste, Vte, Zte, yte = tensors(feat_test)

    class Net(nn.Module):
        def __init__(self, nf):
            super().__init__()
            self.c = nn.Sequential(nn.Conv1d(nf, 64, 5, padding=2), nn.ReLU(),
                                   nn.Conv1d(64, 64, 5, padding=4, dilation=2), nn.ReLU(),
                                   nn.Conv1d(64, 64, 5, padding=8, dilation=4), nn.ReLU())
            self.h = nn.Sequential(nn.Linear(128 + 3, 64), nn.ReLU(), nn.Linear(64, 2))

        def forward(self, x, v, z):
            h = self.c(x) * v[:, None, :]
            mean = h.sum(2) / v.sum(1, keepdim=True).clamp(min=1)
            peak = (h - 1e4 * (1 - v[:, None, :])).amax(2)
            return self.h(torch.cat([mean, peak, z], 1))

    net = Net(Str.shape[1])
    opt = torch.optim.Adam(net.parameters(), 1e-3)
    val, trn = np.arange(N_VAL), np.arange(N_VAL, len(ytr))

    def predict(S, V, Z):
        net.eval()
        with torch.no_grad():
            p = torch.cat([net(S[i:i + 500], V[i:i + 500], Z[i:i + 500]).argmax(1) for i in range(0, len(S), 500)])
        net.train()
        return p

    best, state = -1.0, None
    for _ in range(epochs):
        perm = rng.permutation(trn)
        for i in range(0, len(perm), 64):
            b = perm[i:i + 64]
            loss = nn.functional.cross_entropy(net(Str[b], Vtr[b], Ztr[b]), ytr[b])
            opt.zero_grad()
            loss.backward()
            opt.step()
        v = (predict(Str[val], Vtr[val], Ztr[val]) == ytr[val]).float().mean().item()
        if v > best:
            best, state = v, {k: t.clone() for k, t in net.state_dict().items()}
    net.load_state_dict(state)
    return (predict(Ste, Vte, Zte) == yte).numpy(), best


def keep(directory, kept):
    """What the table needs of a run, small enough to ship: each decoder's right/wrong per test
    track and seed, and the array's estimates against the truth."""
    feat = np.load(os.path.join(directory, "features_test.npz"))
    valid = feat["valid"].astype(bool)
    out = {f"correct_{c}": np.stack([np.load(os.path.join(directory, f"correct_{c}_{s}.npy")) for s in SEEDS])
           for c in CONFIGS}
    out.update(kin=feat["kin"], kin_true=feat["kin_true"],
               az_error=np.abs(feat["az"][valid] - feat["truth"][..., 1][valid]).astype(np.float32),
               range_error=np.abs(feat["range"][valid] - feat["truth"][..., 0][valid]).astype(np.float32))
    np.savez_compressed(kept, **out)


def table(kept, out):
    k = np.load(kept)
    correct = {c: k[f"correct_{c}"] for c in CONFIGS}
    lines = ["# Adults against children over a track: one antenna against an 8-element array", "",
             "Generated by `/usr/bin/python3 docs/results/adult_child_array.py table` from "
             "[adult_child_array_kept.npz](adult_child_array_kept.npz), what the table needs of the runs of "
             "`draw` and `train` (the set-up is the script's docstring): walking adults and children "
             "moving straight at any heading, up to 64 frames (2.05 s), 20 dB per pilot and element, "
             f"{correct['one'].shape[1]} test tracks shared by every decoder, three training seeds.", "",
             "Each decoder tells the two classes apart (trained on these two only): its accuracy is "
             "the pair's pairwise accuracy.", "",
             "| decoder | accuracy (mean of seeds) | seeds |", "|---|---:|---|"]
    names = {"one": "one antenna (element 0's Doppler pilots)", "beam": "8 elements, beamformed",
             "beam_kin": "8 elements, beamformed, with the track's speed and heading",
             "beam_oracle": "8 elements, beamformed, with the true speed and heading"}
    for c in CONFIGS:
        acc = correct[c].mean(1)
        lines.append(f"| {names[c]} | {acc.mean():.3f} | {', '.join(f'{a:.3f}' for a in acc)} |")
    pairs = [("beam", "one"), ("beam_kin", "beam"), ("beam_kin", "one"), ("beam_oracle", "beam_kin")]
    rng = np.random.default_rng(2026)
    n = correct["one"].shape[1]
    boot = rng.integers(0, n, size=(10000, n))
    rows, pvals = [], []
    for a_, b_ in pairs:
        diff = correct[a_].mean(0) - correct[b_].mean(0)  # per test track, mean over seeds
        means = diff[boot].mean(1)
        p = min(1.0, 2 * min((means <= 0).mean(), (means >= 0).mean()) + 1.0 / len(boot))
        rows.append((a_, b_, diff.mean(), np.percentile(means, 2.5), np.percentile(means, 97.5)))
        pvals.append(p)
    lines += ["", "Paired over the same test tracks (accuracy difference, 95 % bootstrap interval, "
              "Holm-corrected p over the four comparisons):", "",
              "| comparison | difference | 95 % interval | p (Holm) |", "|---|---:|---|---:|"]
    for (a_, b_, m, lo, hi), p in zip(rows, holm(pvals)):
        lines.append(f"| {names[a_]} − {names[b_]} | {m:+.3f} | [{lo:+.3f}, {hi:+.3f}] | {p:.4f} |")
    az_err = np.percentile(k["az_error"], [50, 90])
    rng_err = np.percentile(k["range_error"], [50, 90])
    speed_err = np.abs(k["kin"][:, 0] / k["kin_true"][:, 0] - 1)
    cos_err = np.abs(k["kin"][:, 1] - k["kin_true"][:, 1])
    lines += ["", "The array's estimates on the test tracks: per frame, the azimuth's median error "
              f"{az_err[0] * 1e3:.2f} mrad (90th percentile {az_err[1] * 1e3:.2f}) and the range's "
              f"{rng_err[0]:.2f} m ({rng_err[1]:.2f}; a walker's body spreads over both, and a fade or a "
              "limb moves a few frames' peaks far, which the robust line leaves out); per track, the "
              "speed's median relative error "
              f"{np.median(speed_err) * 100:.1f} % (90th percentile {np.percentile(speed_err, 90) * 100:.1f} %) "
              f"and the heading cosine's median error {np.median(cos_err):.3f}.", ""]
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("step", choices=["draw", "train", "table"])
    ap.add_argument("--dir", help="draw, train: where the tracks, features and predictions go; table: "
                    "first keep that run's results in --kept")
    ap.add_argument("--kept", default=os.path.join(here, "adult_child_array_kept.npz"))
    ap.add_argument("--out", default=os.path.join(here, "adult_child_array.md"))
    ap.add_argument("--configs", default=",".join(CONFIGS), help="train: these decoders only (comma-separated)")
    a = ap.parse_args()
    if a.step == "table":
        if a.dir:
            keep(a.dir, a.kept)
        return table(a.kept, a.out)
    if not a.dir:
        ap.error(f"{a.step} needs --dir")
    os.makedirs(a.dir, exist_ok=True)
    from gnuradio import sems
    if a.step == "draw":
        for name in SETS:
            draw(sems, name, os.path.join(a.dir, f"tracks_{name}.npz"))
        return
    feats = {}
    for name in SETS:  # computed once: a second train process (other --configs) reads them
        path = os.path.join(a.dir, f"features_{name}.npz")
        if not os.path.exists(path):
            np.savez(path, **features(sems, os.path.join(a.dir, f"tracks_{name}.npz"), NOISE_SEED[name]))
        feats[name] = dict(np.load(path))
    for c in a.configs.split(","):
        for s in SEEDS:
            t0 = time.time()
            correct, val = train_one(feats["train"], feats["test"], c, s)
            np.save(os.path.join(a.dir, f"correct_{c}_{s}.npy"), correct)
            print(f"{c} seed {s}: validation {val:.3f}, test {correct.mean():.4f} ({time.time() - t0:.0f} s)", flush=True)


if __name__ == "__main__":
    sys.exit(main())
