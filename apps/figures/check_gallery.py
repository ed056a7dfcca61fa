#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: the micro-Doppler gallery's series against what the physics predicts.

    check_gallery.py <sems_gallery> <scenes folder> <work folder> [--frames F]

Runs sems_gallery on the kinematic library's fixed scenes (examples/scenes, paper frame,
N = 32, consecutive frames, noiseless) and asserts per class, on the slow time of one
subcarrier (the spectrum is the mean |STFT|^2 over 128 ms Hann windows, bins of 7.8 Hz):
  adult, child   the strongest Doppler within 2 bins of the torso line 2v/lambda; the
                 spectrum (down to -40 dB of its peak) reaches at least 3 and at most 5 times it;
  quadcopter,    the blade flash period measured from the high-pass (|f - body| > 100 Hz)
  hexacopter     slow-time envelope equals 1/(K f_rot) for even K, 1/(2K f_rot) for odd K within
                 5 %, and the flashes fall on the predicted times (within 1/8 of the period);
  car            the strongest Doppler within 2 bins of the body line; >= 99 % of the energy in
                 [-2 bins, 2 nu_body + 2 bins], and some (>= 0.5 %) above 1.5 nu_body;
  bicyclist      the strongest Doppler within 2 bins of the body line; the rims reach 2 nu_body
                 (>= 0.5 % of the energy in [1.8, 2] nu_body + 2 bins, < 0.5 % beyond it). Its
                 pedal sidebands (nu_body +- k 1.4 Hz) interleave with the rims' (+- k 2.2 Hz):
                 together a comb of 0.2 Hz, periodic over 5 s, not resolved in a 1-2 s series.
Exit 1 with every failed check named.
"""
import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_gallery import CLASSES, flash_phase, flash_rate, read_series  # noqa: E402

WINDOW_S = 0.128


def welch(x, T, window_s=WINDOW_S):
    """Mean |STFT|^2 over Hann windows (half overlap), no zero padding: (f ascending, power, bin)."""
    w = int(round(window_s / T))
    win = np.hanning(w)
    starts = np.arange(0, len(x) - w + 1, w // 2)
    X = np.fft.fftshift(np.fft.fft(np.stack([x[s:s + w] * win for s in starts]), axis=1), axes=1)
    f = np.fft.fftshift(np.fft.fftfreq(w, T))
    return f, np.mean(np.abs(X) ** 2, axis=0), 1.0 / (w * T)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("gallery")
    ap.add_argument("scenes")
    ap.add_argument("work")
    ap.add_argument("--frames", type=int, default=40, help="frames of 32 symbols (default 40: 1.28 s)")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    subprocess.run([args.gallery, "--scenes", args.scenes, "--out", args.work, "--frames", str(args.frames)],
                   check=True, stdout=subprocess.DEVNULL)

    failures = []

    def check(ok, what):
        print(("ok    " if ok else "FAIL  ") + what)
        if not ok:
            failures.append(what)

    for c in CLASSES:
        meta, t, x = read_series(os.path.join(args.work, c + ".csv"))
        T = meta["symbol_interval_s"]
        nu = meta["body_hz"]
        model = meta["model"]
        f, P, bin_hz = welch(x, T)
        total = P.sum()
        peak = f[np.argmax(P)]
        if model in ("walker", "wheels", "scatterers"):
            check(abs(peak - nu) <= 2 * bin_hz,
                  f"{c}: strongest Doppler {peak:.1f} Hz within 2 bins ({2 * bin_hz:.1f} Hz) of the body line {nu:.1f} Hz")
        if model == "walker":
            reach = f[P >= P.max() * 1e-4].max()
            check(3 * nu <= reach <= 5 * nu,
                  f"{c}: spectrum (to -40 dB) reaches {reach:.1f} Hz = {reach / nu:.2f} x 2v/lambda, in [3, 5]")
        elif model == "rotor":
            K = int(meta["blades"])
            pred = meta["flash_period_s"]
            rule = "1/(K f_rot)" if K % 2 == 0 else "1/(2K f_rot)"
            rate, _, _ = flash_rate(x, t, T, nu)
            got = 1.0 / rate
            check(abs(got - pred) <= 0.05 * pred,
                  f"{c}: flash period {got * 1e3:.3f} ms vs {rule} = {pred * 1e3:.3f} ms (K = {K}, "
                  f"f_rot = {meta['rotation_hz']:g} Hz), within 5 %")
            ph, _ = flash_phase(x, t, T, meta)
            check(abs(ph) <= 0.125, f"{c}: flashes {ph:+.3f} periods from the predicted times, within 1/8")
        elif model == "wheels":
            inside = P[(f >= -2 * bin_hz) & (f <= 2 * nu + 2 * bin_hz)].sum() / total
            above = P[f > 1.5 * nu].sum() / total
            check(inside >= 0.99, f"{c}: {inside:.4f} of the energy in [-2 bins, 2 nu_body + 2 bins], >= 0.99")
            check(above >= 0.005, f"{c}: {above:.4f} of the energy above 1.5 nu_body = {1.5 * nu:.0f} Hz, >= 0.005")
        elif model == "scatterers":
            rims = P[(f >= 1.8 * nu) & (f <= 2 * nu + 2 * bin_hz)].sum() / total
            beyond = P[f > 2 * nu + 2 * bin_hz].sum() / total
            check(rims >= 0.005, f"{c}: {rims:.4f} of the energy where the rims reach 2 nu_body ([1.8, 2] nu_body + 2 bins), >= 0.005")
            check(beyond < 0.005, f"{c}: {beyond:.4f} of the energy beyond 2 nu_body + 2 bins, < 0.005")
    if failures:
        print(f"check_gallery: {len(failures)} check(s) failed", file=sys.stderr)
        sys.exit(1)
    print("check_gallery: every class matches its predictions")


if __name__ == "__main__":
    main()
