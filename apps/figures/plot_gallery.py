#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: draw the micro-Doppler gallery of the kinematic class library.

Reads the CSVs sems_gallery writes (one per class: the slow time of one subcarrier, T = 1 ms,
with a header recording the scene and the predicted Doppler lines) and draws, per class, the
spectrogram of that slow time (Hann window of --window-ms, hop --hop-ms,
Doppler in Hz with m/s on the right, v = f*lambda/2, dB scale) with the predictions over it:
the body/torso line 2v/lambda, the walker's feet swing peak (about 4 times it) and the stance
near 0, the wheel tops at twice the body's Doppler and the contact points at 0, the bicyclist's
rim extremes, and for rotors the blade tips (folded into +-1/(2T)) and a strip of the
high-pass slow-time envelope with ticks at the predicted blade flash times
(a blade is perpendicular to the line of sight when cos(2*pi*f*t + phi + 2*pi*k/K) = 0).

The figure docs/reference/micro_doppler_gallery.png is made with (from the source tree,
after building the sems_gallery target):

    build/apps/sems_gallery --frames 64 --out build/gallery
    /usr/bin/python3 apps/figures/plot_gallery.py build/gallery docs/reference/micro_doppler_gallery.png
"""
import argparse
import math
import os
import sys

import numpy as np

CLASSES = ["adult", "child", "quadcopter", "hexacopter", "car", "bicyclist"]


def read_series(path):
    """One sems_gallery CSV: (meta dict of the header's "# key = value" lines, t_s, complex x)."""
    meta = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            if " = " in line:
                k, v = line[1:].strip().split(" = ", 1)
                try:
                    meta[k] = float(v)
                except ValueError:
                    meta[k] = v
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=0, dtype=str)
    data = data[1:].astype(float)  # drop the column names
    return meta, data[:, 1], data[:, 2] + 1j * data[:, 3]


def spectrum(x, T):
    """Hann-windowed periodogram of the whole series: (f in Hz ascending, power)."""
    n = len(x)
    X = np.fft.fftshift(np.fft.fft(x * np.hanning(n)))
    f = np.fft.fftshift(np.fft.fftfreq(n, T))
    return f, np.abs(X) ** 2


def stft(x, T, window_s, hop_s, nfft=512):
    """|STFT|^2 with a Hann window: (frame centre times, f ascending, power [f, time])."""
    w = max(8, int(round(window_s / T)))
    hop = max(1, int(round(hop_s / T)))
    win = np.hanning(w)
    starts = np.arange(0, len(x) - w + 1, hop)
    frames = np.stack([x[s:s + w] * win for s in starts])
    X = np.fft.fftshift(np.fft.fft(frames, n=max(nfft, w), axis=1), axes=1)
    f = np.fft.fftshift(np.fft.fftfreq(max(nfft, w), T))
    return (starts + w / 2) * T, f, (np.abs(X) ** 2).T


def highpass_envelope(x, T, body_hz, cutoff_hz=100.0):
    """|y|^2, y = x with every (folded) component within cutoff_hz of the body line removed."""
    n = len(x)
    X = np.fft.fft(x)
    f = np.fft.fftfreq(n, T)
    fs = 1.0 / T
    d = np.mod(f - body_hz + fs / 2, fs) - fs / 2  # circular distance to the body line
    X[np.abs(d) <= cutoff_hz] = 0
    return np.abs(np.fft.ifft(X)) ** 2


def flash_concentration(e, t, rates_hz, bins=40, width=12):
    """For each folding rate, the largest share of the envelope's energy that falls within a
    window of width/bins of the folded period (0.3 by default) around one phase."""
    out = np.empty(len(rates_hz))
    total = e.sum()
    for i0 in range(0, len(rates_hz), 256):
        r = rates_hz[i0:i0 + 256]
        idx = (np.floor(np.mod(np.outer(r, t), 1.0) * bins).astype(int) + bins * np.arange(len(r))[:, None]).ravel()
        s = np.bincount(idx, weights=np.tile(e, len(r)), minlength=bins * len(r)).reshape(len(r), bins)
        c = np.cumsum(np.concatenate([s, s[:, :width]], axis=1), axis=1)
        out[i0:i0 + 256] = (c[:, width:width + bins] - c[:, :bins]).max(axis=1) / total
    return out


def flash_rate(x, t, T, body_hz, lo_hz=20.0, step_hz=0.05, tie=0.03):
    """The blade flash rate (Hz) from the slow time: fold the high-pass envelope (|f - body| > 100 Hz)
    at every rate from lo_hz to 1/(2T) and find where its energy gathers in the narrowest phase
    window (flashes every 1/rate). Twice the flash rate folds the flashes together as well (every
    other window empty), so the lowest rate within `tie` of the best is the flash rate.
    Returns (rate, rates, concentration)."""
    e = highpass_envelope(x, T, body_hz)
    rates = np.arange(lo_hz, 0.5 / T - 1.0, step_hz)
    s = flash_concentration(e, t, rates)
    return rates[np.nonzero(s >= s.max() - tie)[0].min()], rates, s


def flash_phase(x, t, T, meta, bins=32):
    """Where the envelope folded at the predicted flash period peaks, as a fraction of the
    period after the predicted flash times (0 = on the predicted flashes), and the profile."""
    e = highpass_envelope(x, T, meta["body_hz"])
    P = meta["flash_period_s"]
    ph = np.mod(t - meta["first_flash_s"], P) / P
    idx = np.minimum((ph * bins).astype(int), bins - 1)
    prof = np.bincount(idx, weights=e, minlength=bins) / np.maximum(np.bincount(idx, minlength=bins), 1)
    k = int(np.argmax(prof))
    c = (k + 0.5) / bins
    return (c if c <= 0.5 else c - 1.0), prof


def fold_hz(f, fs):
    return (f + fs / 2) % fs - fs / 2


def ylimits(meta, fs):
    b = meta["body_hz"]
    model = meta["model"]
    if model == "walker":
        return -0.8 * b - 10, 5 * b + 10
    if model == "wheels":
        return min(-40, meta["wheel_contact_hz"] - 40), min(fs / 2, meta["wheel_top_hz"] + 60)
    if model == "scatterers":
        return meta["scatterer_min_hz"] - 40, meta["scatterer_max_hz"] + 40
    return -fs / 2, fs / 2


def draw(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.gridspec import GridSpec

    series = {}
    for c in args.classes.split(","):
        p = os.path.join(args.csv_dir, c + ".csv")
        if not os.path.isfile(p):
            sys.exit(f"plot_gallery: {p} missing (run sems_gallery --out {args.csv_dir} first)")
        series[c] = read_series(p)
    names = list(series)
    cols = 2
    rows = (len(names) + cols - 1) // cols
    fig = plt.figure(figsize=(15, 5.6 * rows))
    outer = GridSpec(rows, cols, figure=fig, hspace=0.45, wspace=0.3, left=0.06, right=0.96, top=0.93, bottom=0.04)
    first = next(iter(series.values()))[0]
    fig.suptitle(
        f"Micro-Doppler of the kinematic class library: one target per class, heading 0 (approaching), noiseless\n"
        f"slow time of subcarrier {int(first['subcarrier'])} at T = {first['symbol_interval_s'] * 1e3:g} ms, "
        f"f_c = {first['carrier_hz'] / 1e9:g} GHz (v = f·λ/2 = f·{first['wavelength_m'] / 2:.3g} m/s); "
        f"STFT Hann {args.window_ms:g} ms, hop {args.hop_ms:g} ms",
        fontsize=11)
    line_kw = dict(lw=1.3, alpha=0.95)
    for i, c in enumerate(names):
        meta, t, x = series[c]
        T = meta["symbol_interval_s"]
        fs = 1.0 / T
        lam = meta["wavelength_m"]
        b = meta["body_hz"]
        model = meta["model"]
        cell = outer[i // cols, i % cols]
        if model == "rotor":
            sub = cell.subgridspec(2, 2, height_ratios=[3.0, 1.0], hspace=0.55, wspace=0.25)
            ax = fig.add_subplot(sub[0, :])
            ax_t = fig.add_subplot(sub[1, 0])
            ax_p = fig.add_subplot(sub[1, 1])
        else:
            ax = fig.add_subplot(cell)
        tt, f, S = stft(x, T, args.window_ms / 1e3, args.hop_ms / 1e3)
        db = 10 * np.log10(S / S.max() + 1e-30)
        im = ax.pcolormesh(tt, f, db, shading="auto", cmap="magma", vmin=-args.range_db, vmax=0, rasterized=True)
        lo, hi = ylimits(meta, fs)
        ax.set_ylim(lo, hi)
        ax.set_xlim(tt[0], tt[-1])
        ax.set_xlabel("time (s)")
        ax.set_ylabel("Doppler (Hz)")
        sec = ax.secondary_yaxis("right", functions=(lambda v, l=lam: v * l / 2, lambda v, l=lam: 2 * v / l))
        sec.set_ylabel("radial velocity (m/s)")
        fig.colorbar(im, ax=ax, pad=0.13, fraction=0.035).set_label("dB (re peak)")
        lines = [(b, "cyan", "-", f"body 2v/λ = {b:.0f} Hz")]
        title = f"{c}: {model}, v = {meta['speed_mps']:g} m/s"
        if model == "walker":
            lines.append((meta["feet_swing_peak_hz"], "lime", "--", f"feet swing peak ≈ 4·(2v/λ) = {meta['feet_swing_peak_hz']:.0f} Hz"))
            lines.append((meta["stance_hz"], "white", ":", "stance foot ≈ 0"))
            title += f", height {meta['height_m']:g} m, gait cycle {meta['gait_cycle_s']:.2f} s"
        elif model == "wheels":
            lines.append((meta["wheel_top_hz"], "lime", "--", f"wheel tops 2·(2v/λ) = {meta['wheel_top_hz']:.0f} Hz"))
            lines.append((meta["wheel_contact_hz"], "white", ":", "contact points 0 Hz"))
            title += f", {int(meta['wheels'])} wheels R = {meta['wheel_radius_m']:g} m ({meta['wheel_rev_hz']:.1f} rev/s)"
        elif model == "scatterers":
            lines.append((meta["scatterer_max_hz"], "lime", "--", f"rim tops {meta['scatterer_max_hz']:.0f} Hz ≈ 2·(2v/λ)"))
            lines.append((meta["scatterer_min_hz"], "white", ":", f"rim bottoms {meta['scatterer_min_hz']:.0f} Hz"))
            rates = str(meta["sideband_rates_hz"]).split()
            title += f"\nsidebands at body ± k·{' / '.join(rates)} Hz (pedals / wheels)"
        elif model == "rotor":
            K = int(meta["blades"])
            fr = meta["rotation_hz"]
            tip = meta["tip_doppler_hz"]
            for s, name in ((1, "+tip"), (-1, "−tip")):
                ff = fold_hz(b + s * tip, fs)
                lines.append((ff, "lime", "--", f"body {name} ({b + s * tip:+.0f} Hz) folded to {ff:+.0f} Hz"))
            P = meta["flash_period_s"]
            rule = "1/(K·f)" if K % 2 == 0 else "1/(2K·f)"
            title += (f", {int(meta['rotors'])}×{K} blades L = {meta['blade_length_m']:g} m at {fr:g} rev/s\n"
                      f"tips ±(2/λ)·2πfL·cosβ = ±{tip:.0f} Hz; flashes every {rule} = {P * 1e3:.2f} ms")
        for y, col, ls, lab in lines:
            ax.axhline(y, color=col, ls=ls, label=lab, **line_kw)
        ax.legend(loc="upper right", fontsize=7.5, framealpha=0.75)
        ax.set_title(title, fontsize=9.5)
        if model == "rotor":
            P = meta["flash_period_s"]
            t0 = meta["first_flash_s"]
            e = highpass_envelope(x, T, b)
            span = min(t[-1], args.zoom_ms / 1e3)
            sel = t <= span
            ax_t.vlines(t[sel] * 1e3, 0, e[sel], color="k", lw=1.2)
            ax_t.plot(t[sel] * 1e3, e[sel], "k.", ms=3)
            flashes = t0 + P * np.arange(0, int(span / P) + 1)
            for k, tf in enumerate(flashes):
                ax_t.axvline(tf * 1e3, color="tab:red", lw=0.9, alpha=0.8, label="predicted flash" if k == 0 else None)
            ax_t.set_xlim(0, span * 1e3)
            ax_t.set_xlabel("time (ms)")
            ax_t.set_ylabel("|high-pass|²", fontsize=8)
            ax_t.set_yticks([])
            ax_t.set_title("slow time, |f − body| > 100 Hz", fontsize=8.5)
            ax_t.legend(loc="upper right", fontsize=7)
            ph = np.mod(t - t0 + P / 2, P) - P / 2
            ax_p.plot(ph * 1e3, e, ".", ms=2, color="k", alpha=0.5)
            ax_p.axvline(0, color="tab:red", lw=1.2)
            ax_p.set_xlim(-P / 2 * 1e3, P / 2 * 1e3)
            ax_p.set_yticks([])
            ax_p.set_xlabel("time from the nearest predicted flash (ms)")
            meas, _, _ = flash_rate(x, t, T, b)
            ax_p.set_title(f"folded at {P * 1e3:.3f} ms; measured period {1e3 / meas:.3f} ms", fontsize=8.5)
    os.makedirs(os.path.dirname(os.path.abspath(args.png)) or ".", exist_ok=True)
    fig.savefig(args.png, dpi=args.dpi)
    print(f"plot_gallery: wrote {args.png}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv_dir", help="folder of <class>.csv from sems_gallery --out")
    ap.add_argument("png", help="the figure to write")
    ap.add_argument("--classes", default=",".join(CLASSES), help="comma-separated classes (default: all six)")
    ap.add_argument("--window-ms", type=float, default=128.0, help="STFT Hann window (default 128 ms)")
    ap.add_argument("--hop-ms", type=float, default=4.0, help="STFT hop (default 4 ms)")
    ap.add_argument("--range-db", type=float, default=50.0, help="colour range below the peak (default 50 dB)")
    ap.add_argument("--zoom-ms", type=float, default=40.0, help="rotor strips: slow time shown (default 40 ms)")
    ap.add_argument("--dpi", type=int, default=110)
    draw(ap.parse_args())


if __name__ == "__main__":
    main()
