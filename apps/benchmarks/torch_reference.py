#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""PyTorch (Python) reference of the shipped decoders, the anchor of the decoder benchmarks.

The same networks as lib/learning/networks/spectral_classifier_decoder.cc (kind "classifier_spectral")
and lib/learning/networks/delay_decoder.cc (kind "delay_correlation": projection, dictionary
correlation, orthogonal-matching-pursuit residual maps, phase reference, dilated residual
CNN, local soft-argmax), written with torch.nn.functional and reading the SAME weights: the
bundle's decoder.pt (written by LibTorch's torch::save of the module) loads with
torch.jit.load, whose state_dict() holds every parameter and buffer under the C++ names.
The input is prepared as bundle_decoder.cc does: the (batch, N_p) complex pilots, in mask
order (sorted by symbol, then subcarrier), scattered into a zero B x 2 x N x M grid, then
normalised per frame (nn::normalise_frames).

Not reproduced: the delay decoder's least-squares refinement (refine_paths > 0), which is
C++ only (baselines' multipath_fitter). Compare against a bundle with refine_paths = 0
(with_refinement_off() writes one); `check` and `bench` do so.

Usage (GNU Radio's Python; `from gnuradio import sems` must import, e.g. with
PYTHONPATH=build/python_pkg):
  torch_reference.py check [--models DIR] [--classifier DIR]
                                            C++ bundle_decoder == this reference, and a
                                            perturbed weight breaks the agreement (--classifier:
                                            check that classifier bundle instead of DIR/classifier)
  torch_reference.py bench [--models DIR] [--batches 1,32,256] [--frames 2048] [--repeat 5]
                                            frames/s of both, 1 intra-op thread, same run
"""
import argparse
import json
import math
import os
import shutil
import sys
import tempfile
import time

import numpy as np
import torch
import torch.nn.functional as F


class Reference:
    """A bundle's decoder in PyTorch: __call__(obs) takes (batch, N_p) complex64 pilots."""

    def __init__(self, bundle_dir):
        with open(os.path.join(bundle_dir, "bundle.json")) as f:
            self.info = json.load(f)
        with open(os.path.join(bundle_dir, self.info.get("mask_file", "mask.json"))) as f:
            mask = json.load(f)
        fr = self.info["frame"]
        self.n, self.m = fr["n_symbols"], fr["n_subcarriers"]
        self.index = torch.tensor(sorted(n * self.m + m for n, m in mask["pilots"]), dtype=torch.long)
        self.np = len(self.index)
        self.mask = torch.zeros(self.n * self.m)
        self.mask[self.index] = 1.0
        self.mask = self.mask.view(self.n, self.m)
        self.cols = (self.mask.sum(0) > 0).nonzero().squeeze(1)  # the subcarriers with pilots
        self.grid_m, self.grid_index = self.m, self.index
        if self.info["decoder"]["kind"] == "classifier_spectral":
            column = torch.full((self.m,), -1, dtype=torch.long)
            column[self.cols] = torch.arange(len(self.cols))
            self.grid_m = len(self.cols)
            self.grid_index = (self.index // self.m) * self.grid_m + column[self.index % self.m]
        weights = os.path.join(bundle_dir, self.info.get("weights_file", "decoder.pt"))
        self.w = {k: v.detach().clone() for k, v in torch.jit.load(weights).state_dict().items()}
        self.kind = self.info["decoder"]["kind"]
        self.dense = {}  # the small convolutions' dense matrices, built on first use
        self.s = self.info["decoder"]["settings"]
        if self.kind == "classifier_spectral":
            k = self.s["doppler_bins"]
            kn = torch.remainder(torch.arange(k).unsqueeze(1) * torch.arange(self.n).unsqueeze(0), k)
            arg = kn.double() * (2.0 * math.pi / k)  # exact phases, as the C++ builds them
            self.dft_cos, self.dft_sin = torch.cos(arg).float(), torch.sin(arg).float()
            self.dft = torch.cat([torch.cat([self.dft_cos, self.dft_sin], 1), torch.cat([-self.dft_sin, self.dft_cos], 1)], 0)
            self.chirp_bins = self.s.get("chirp_bins", 0)  # absent: the legacy network, no tone fit
            self.chirp_min_pilots = self.s.get("chirp_min_pilots", 1)  # absent: every observed subcarrier
            if self.chirp_bins > 0:  # π α_j (n - (N-1)/2)², the rates α_j from the C++ definition
                from gnuradio import sems
                rates = torch.tensor(sems.classifier_chirp_rates(json.dumps(self.s), self.n), dtype=torch.double)
                centred = torch.arange(self.n, dtype=torch.double) - 0.5 * (self.n - 1)
                self.chirp_phase = ((math.pi * rates).unsqueeze(1) * centred.square().unsqueeze(0)).float()
            self.range_bins = self.s.get("range_bins", 0)  # absent: the legacy pooled profile
            if self.range_bins > 0:  # the range gate's exp(+j2π m l / L) on the mask's subcarriers, once
                nl = self.range_bins
                # conj(delay_phasor(m, l·M/L, M)) as core/array/steering.h computes it: cis of the
                # cycles -m·l/L reduced to [0, 1) in double, then conjugated.
                x = -self.cols.double().unsqueeze(1) * (torch.arange(nl).double() * self.m / nl).unsqueeze(0) / self.m
                cycles = x - torch.floor(x)
                self.range_cos = torch.cos(2.0 * math.pi * cycles).float()
                self.range_sin = (-torch.sin(2.0 * math.pi * cycles)).float()
        elif self.kind == "delay_correlation":
            if self.s.get("refine_paths", 0) > 0:
                print("torch_reference: %s has refine_paths = %d; the reference runs the network only "
                      "(refinement off)" % (bundle_dir, self.s["refine_paths"]), file=sys.stderr)
        else:
            raise ValueError("torch_reference: %s: decoder kind %r has no reference (known: "
                             "classifier_spectral, delay_correlation)" % (bundle_dir, self.kind))

    # -- input, as bundle_decoder.cc and task_decoder.cc prepare it
    def grid(self, obs):
        o = torch.view_as_real(torch.from_numpy(np.ascontiguousarray(obs, dtype=np.complex64)))  # B x N_p x 2
        # As bundle_decoder does: the spectral classifier's grid holds only the subcarriers that
        # carry pilots (the others are zero and add nothing to the normalisation, the profile
        # or the zero-Doppler means).
        g = torch.zeros(o.shape[0], 2, self.n * self.grid_m)
        g.index_copy_(2, self.grid_index, o.permute(0, 2, 1))
        g = g.view(-1, 2, self.n, self.grid_m)
        peak = g.abs().flatten(1).amax(1).clamp_min(1e-30).view(-1, 1, 1, 1)
        g = g / peak
        power = (g * g).flatten(1).sum(1) / self.np
        return g / torch.sqrt(power + 1e-12).view(-1, 1, 1, 1)

    def bn(self, x, name):
        w = self.w
        return F.batch_norm(x, w[name + ".running_mean"], w[name + ".running_var"], w[name + ".weight"],
                            w[name + ".bias"], False, 0.0, 1e-5)

    # -- classifier_spectral
    def profile(self, g):
        # As the C++: one real product [fr; fi] = [[cos, sin], [-sin, cos]] [re; im].
        b, m, k = g.shape[0], g.shape[3], self.dft_cos.shape[0]
        f = torch.matmul(self.dft, g.reshape(b, 2 * self.n, m))
        if self.range_bins > 0:  # range gate: the Doppler profile of the strongest delay bin
            rc, rs = self.range_cos, self.range_sin
            fr, fi = f[:, :k], f[:, k:]
            rr = torch.matmul(fr, rc) - torch.matmul(fi, rs)
            ri = torch.matmul(fr, rs) + torch.matmul(fi, rc)
            p = rr * rr + ri * ri
            gate = p.sum(1).argmax(1)
            s = p.gather(2, gate.view(-1, 1, 1).expand(p.shape[0], p.shape[1], 1)).squeeze(2)
        else:
            s = f.square().view(b, 2, k, m).sum((1, 3))
        s = s / (s.mean(1, True) + 1e-12)
        return torch.log(s + 1e-3)

    def tone_fit(self, g, mask, profile):
        # As spectral_classifier_decoder.cc: per chirp rate, the share of the subcarriers'
        # slow-time energy one common chirp explains, its frequency searched from the profile's
        # peak by two parabolic steps.
        n_obs = mask.sum(0)
        if self.chirp_min_pilots > 1:  # only subcarriers with chirp_min_pilots or more pilots: the others zeroed
            counted = (n_obs >= self.chirp_min_pilots - 1e-3).to(g.dtype)
            g, n_obs = g * counted, n_obs * counted
        zr, zi = g[:, 0], g[:, 1]  # B x N x M'
        energy = (n_obs * (zr.square() + zi.square()).sum(1)).sum(1, True) + 1e-12
        nn = torch.arange(self.n, dtype=g.dtype).view(1, 1, -1)
        k = self.dft_cos.shape[0]

        def power_at(f):
            theta = 2.0 * math.pi * f.unsqueeze(2) * nn + self.chirp_phase.unsqueeze(0)
            c, sn = torch.cos(theta), torch.sin(theta)
            re = torch.matmul(c, zr) + torch.matmul(sn, zi)
            im = torch.matmul(c, zi) - torch.matmul(sn, zr)
            return (re.square() + im.square()).sum(2)

        def vertex(lo, mid, hi, limit):
            den = lo - 2 * mid + hi
            return torch.where(den < 0, 0.5 * (lo - hi) / den.clamp_max(-1e-30), torch.zeros_like(den)).clamp(-limit, limit)

        k0 = (profile.flatten(1).argmax(1) % k).to(g.dtype).view(-1, 1).expand(g.shape[0], self.chirp_bins)
        f0, step = k0 / k, torch.full_like(k0, 1.0 / k)
        f1 = f0 + step * vertex(power_at(f0 - step), power_at(f0), power_at(f0 + step), 0.5)
        h = 1.0 / (8.0 * k)
        p_mid = power_at(f1)
        f2 = f1 + h * vertex(power_at(f1 - h), p_mid, power_at(f1 + h), 2.0)
        f = torch.where(power_at(f2) >= p_mid, f2, f1)
        share = (power_at(f) / energy).clamp(0.0, 1.0)
        return torch.log(1.0 - share + 1e-4)

    # The C++ inference's convolution: small ones as one product with their dense circulant
    # matrix (spectral_classifier_decoder.cc, dense_conv_max_macs), large ones through conv1d.
    def conv(self, x, name, p, with_bn=False):
        w, b = self.w[name + ".weight"], self.w[name + ".bias"]
        co, ci, k = w.shape
        bins = x.shape[2]
        if co * ci * bins * bins > 65536:
            if with_bn:
                x = self.bn(x, "bn")
            return F.conv1d(F.pad(x, (p, p), mode="circular"), w, b)
        if name not in self.dense:
            shift = torch.zeros(k, bins, bins)  # [j, s, t]
            for j in range(k):
                for t in range(bins):
                    shift[j, (t + j - k // 2) % bins, t] = 1.0
            d = torch.matmul(w.reshape(co * ci, k), shift.reshape(k, bins * bins))
            m = d.view(co, ci, bins, bins).permute(1, 2, 0, 3).reshape(ci * bins, co * bins)
            bias = b.repeat_interleave(bins)
            if with_bn:  # the BatchNorm in front folded in, as the C++ does
                scale = self.w["bn.weight"] / torch.sqrt(self.w["bn.running_var"] + 1e-5)
                offset = self.w["bn.bias"] - self.w["bn.running_mean"] * scale
                bias = bias + torch.matmul(offset.repeat_interleave(bins), m)
                m = m * scale.repeat_interleave(bins).unsqueeze(1)
            self.dense[name] = (m.contiguous(), bias.contiguous())
        m, bias = self.dense[name]
        return torch.addmm(bias, x.reshape(x.shape[0], ci * bins), m).view(x.shape[0], co, bins)

    def classifier(self, g):
        w, mti = self.w, self.s.get("mti", "none")
        mask = self.mask.index_select(1, self.cols)  # g has only these columns (see grid)
        if mti != "none":  # remove_zero_doppler: each subcarrier's mean over its pilots
            clean = g - mask * (g.sum(2, True) / mask.sum(0, True).clamp_min(1.0))
        last = g if mti == "none" else clean  # the stage the tone fit sees
        x = (self.profile(g).unsqueeze(1) if mti == "none" else self.profile(clean).unsqueeze(1) if mti == "mean"
             else torch.stack([self.profile(g), self.profile(clean)], 1))
        tone = self.tone_fit(last, mask, x[:, -1]) if self.chirp_bins > 0 else None
        p = self.s["kernel"] // 2
        slope = self.s.get("conv_slope", 0.0)  # absent: the legacy ReLU
        x = F.leaky_relu(self.conv(x, "conv1", p, with_bn=True), slope)  # BatchNorm, conv1
        x = F.leaky_relu(self.conv(x, "conv2", p), slope)
        x = F.leaky_relu(F.linear(x.flatten(1), w["fc1.weight"], w["fc1.bias"]), 0.1)
        if tone is not None:  # the tone fit's own layer joins the hidden layer
            t = F.linear(self.bn(tone, "tone_bn"), w["tone_fc.weight"], w["tone_fc.bias"])
            x = torch.cat([x, F.leaky_relu(t, 0.1)], 1)
        features = F.linear(x, w["fc2.weight"], w["fc2.bias"])
        logits = F.linear(F.leaky_relu(features, 0.1), w["out.weight"], w["out.bias"])
        if self.s.get("template_frames", 0) > 0:  # the template bank's layer joins the logits
            logits = logits + F.linear(self.template_scores(g), w["templates.out.weight"], w["templates.out.bias"])
        return torch.softmax(logits, -1), features

    def template_scores(self, g):
        # As template_bank.cc: ρ_t = |yᴴt|²/‖y‖², β = N_p/(1 - max ρ), per class the log-mean-exp
        # of β ρ over its templates, normalised over the classes and floored at -30.
        t, ends = self.w["templates.templates"], self.w["templates.class_end"].tolist()
        b = g.shape[0]
        y = g.reshape(b, 2, -1).index_select(2, self.grid_index).reshape(b, -1)  # the pilots, mask order
        energy = y.square().sum(1, True).clamp_min(torch.finfo(torch.float32).tiny)
        yr, yi, tr, ti = y[:, :self.np], y[:, self.np:], t[:, 0], t[:, 1]
        rho = ((yr @ tr.T + yi @ ti.T).square() + (yr @ ti.T - yi @ tr.T).square()) / energy
        best = rho.amax(1, keepdim=True).clamp(0.0, 1.0)
        a = self.np / (1.0 - best).clamp_min(1e-3) * rho
        scores, lo = [], 0
        for hi in ends:
            scores.append(torch.logsumexp(a[:, lo:hi], 1) - math.log(hi - lo) if hi > lo
                          else torch.full((b,), -math.inf))
            lo = hi
        s = torch.stack(scores, 1)
        s = torch.nan_to_num(s - torch.logsumexp(s, 1, True), -30.0, -30.0, -30.0).clamp_min(-30.0)
        return torch.cat([s, torch.log(1.0 - best + 1e-4)], 1)

    # -- delay_correlation
    def residual_maps(self, xr, xi, support, scale):
        y = torch.complex(xr.double(), xi.double())  # B x M
        steer = torch.complex(self.w["dict_cos"].double(), -self.w["dict_sin"].double())  # M x Q
        conj_steer = steer.conj()
        sup = torch.complex(support.double(), torch.zeros_like(support, dtype=torch.double))
        mag = (torch.matmul(y, conj_steer) * scale).abs()
        chosen, out = [], []
        for _ in range(self.s["residual_maps"]):
            chosen.append(mag.argmax(1))
            idx = torch.stack(chosen, 1)
            a = steer.t().index_select(0, idx.flatten()).view(idx.shape[0], idx.shape[1], self.m)
            a = (a * sup.unsqueeze(1)).transpose(1, 2)  # B x M x L
            ah = a.conj().transpose(1, 2)
            g = torch.matmul(ah, a)
            g = g + 1e-9 * torch.eye(g.shape[-1], dtype=g.dtype) * (
                1.0 + torch.real(g.diagonal(0, 1, 2)).amax(-1)).view(-1, 1, 1)
            b = torch.linalg.solve(g, torch.matmul(ah, y.unsqueeze(-1)))
            res = y - torch.matmul(a, b).squeeze(-1)
            mag = (torch.matmul(res, conj_steer) * scale).abs()
            out.append(mag)
        return torch.stack(out, 1).to(xr.dtype)

    def delay(self, x):
        w, s = self.w, self.s
        yr, yi = x[:, 0], x[:, 1]
        xr = torch.matmul(w["proj_re"], yr) - torch.matmul(w["proj_im"], yi)  # B x P x M
        xi = torch.matmul(w["proj_re"], yi) + torch.matmul(w["proj_im"], yr)
        scale = 1.0 / math.sqrt(self.np)
        rr = (torch.matmul(xr, w["dict_cos"]) - torch.matmul(xi, w["dict_sin"])) * scale
        ri = (torch.matmul(xr, w["dict_sin"]) + torch.matmul(xi, w["dict_cos"])) * scale
        maps = None
        if s["residual_maps"] > 0:
            support = (x.abs().sum(1).sum(1) > 0).to(x.dtype)
            maps = self.residual_maps(xr[:, 0], xi[:, 0], support, scale)
        if s["phase_reference"]:
            k = (rr[:, 0].square() + ri[:, 0].square()).argmax(1, True)
            pr, pi = rr[:, 0].gather(1, k), ri[:, 0].gather(1, k)
            norm = torch.sqrt(pr * pr + pi * pi + 1e-20)
            c, sn = (pr / norm).unsqueeze(1), (-pi / norm).unsqueeze(1)
            rr, ri = rr * c - ri * sn, rr * sn + ri * c
        mag = torch.sqrt(rr * rr + ri * ri + 1e-12)
        feat = torch.cat([rr, ri, mag] + ([maps] if maps is not None else []), 1)
        kern, q = s["kernel"], s["q"]
        h = F.relu(self.bn(F.conv1d(feat, w["stem.weight"], None, padding=kern // 2), "stem_bn"))
        d = 1
        for i in range(s["depth"]):
            b = "blocks.%d." % i
            y = F.relu(self.bn(F.conv1d(h, w[b + "conv1.weight"], None, padding=d * (kern // 2), dilation=d), b + "bn1"))
            y = self.bn(F.conv1d(y, w[b + "conv2.weight"], None, padding=d * (kern // 2), dilation=d), b + "bn2")
            h = F.relu(h + y)
            d = min(d * s["dilation_growth"], q)
        logits = F.conv1d(h, w["head.weight"], w["head.bias"]).squeeze(1)
        return self.soft_argmax(logits, w["tau"], s["window"])

    @staticmethod
    def soft_argmax(logits, tau, window):
        q = logits.shape[-1]
        if window <= 0 or 2 * window + 1 >= q:
            return (torch.softmax(logits, -1) * tau).sum(-1)
        center = logits.argmax(-1, True).clamp(window, q - 1 - window)
        idx = center + torch.arange(-window, window + 1).unsqueeze(0)
        z = logits.gather(-1, idx)
        return (torch.softmax(z, -1) * tau.index_select(0, idx.flatten()).view(idx.shape)).sum(-1)

    def __call__(self, obs):
        """Class probabilities (batch x C) or delay indices (batch,), as numpy."""
        with torch.inference_mode():  # as bundle_decoder (c10::InferenceMode)
            g = self.grid(obs)
            if self.kind == "classifier_spectral":
                return self.classifier(g)[0].numpy()
            return self.delay(g).double().numpy()


def with_refinement_off(bundle_dir, out_dir):
    """A copy of bundle_dir in out_dir with decoder.settings.refine_paths = 0; returns out_dir."""
    with open(os.path.join(bundle_dir, "bundle.json")) as f:
        info = json.load(f)
    info["decoder"]["settings"]["refine_paths"] = 0
    os.makedirs(out_dir, exist_ok=True)
    for name in (info.get("mask_file", "mask.json"), info.get("weights_file", "decoder.pt")):
        shutil.copy(os.path.join(bundle_dir, name), os.path.join(out_dir, name))
    with open(os.path.join(out_dir, "bundle.json"), "w") as f:
        json.dump(info, f, indent=2)
    return out_dir


def decoders(models, tmp, classifier=None):
    """(label, C++ call, reference) for the shipped classifier (or `classifier`) and single-path delay bundles."""
    from gnuradio import sems
    cls_dir = classifier or os.path.join(models, "classifier")
    delay_dir = with_refinement_off(os.path.join(models, "delay_single"), os.path.join(tmp, "delay_single"))
    cls, delay = sems.bundle_decoder(cls_dir, 1), sems.bundle_decoder(delay_dir, 1)
    out = [("classifier", cls.classify, Reference(cls_dir)),
           ("delay_single, refine off", delay.estimate_delay_index, Reference(delay_dir))]
    fast_dir = os.path.join(models, "classifier_fast")  # small convolutions: the dense-matrix path
    if os.path.exists(os.path.join(fast_dir, "bundle.json")):
        out.append(("classifier_fast", sems.bundle_decoder(fast_dir, 1).classify, Reference(fast_dir)))
    return out


def observations(rng, batch, n_pilots, snr_db=None):
    """Random pilot observations: a random-phase tone over the pilots plus noise, or pure noise."""
    z = (rng.standard_normal((batch, n_pilots)) + 1j * rng.standard_normal((batch, n_pilots))) / math.sqrt(2)
    if snr_db is not None:
        phase = rng.uniform(0, 2 * math.pi, (batch, 1)) + rng.uniform(-0.6, 0.6, (batch, 1)) * np.arange(n_pilots)
        z = np.exp(1j * phase) + z * 10 ** (-snr_db / 20)
    return z.astype(np.complex64)


def check(models, classifier=None):
    """Assert C++ == reference on random frames, and that one perturbed weight breaks it."""
    torch.set_num_threads(1)
    rng = np.random.default_rng(7)
    tol = {"classifier": 1e-4, "classifier_fast": 1e-4, "delay_single, refine off": 1e-3}
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, cpp, ref in decoders(models, tmp, classifier):
            obs = np.concatenate([observations(rng, 64, ref.np), observations(rng, 64, ref.np, 20.0),
                                  observations(rng, 64, ref.np, 0.0) * np.float32(1e3)])
            a, b = np.asarray(cpp(obs)), ref(obs)
            err = float(np.max(np.abs(a - b)))
            print("%-34s %d frames  max |C++ - PyTorch| = %.3g (tolerance %g)" % (label, len(obs), err, tol[label]))
            if a.shape != b.shape or not err <= tol[label]:
                failures.append("%s: C++ and the reference disagree by %g" % (label, err))
            # A test that can fail: one weight of the last layer moved must break the agreement.
            name = "out.bias" if "out.bias" in ref.w else "head.weight"
            ref.w[name].view(-1)[0] += 0.5
            err_p = float(np.max(np.abs(a - ref(obs))))
            ref.w[name].view(-1)[0] -= 0.5
            print("%-34s perturbed %s: max difference %.3g" % (label, name, err_p))
            if not err_p > 10 * tol[label]:
                failures.append("%s: perturbing %s did not break the agreement (%g)" % (label, name, err_p))
    for f in failures:
        print("FAIL", f)
    return 1 if failures else 0


def bench(models, batches, frames, repeat):
    """Frames/s of the C++ bundle_decoder (through its Python binding, one batch call per
    batch) and of the reference, 1 intra-op thread, interleaved, best of `repeat`: per wall
    second and per CPU second of the calling thread (steadier on a shared machine)."""
    torch.set_num_threads(1)
    rng = np.random.default_rng(1)

    def rate(fn, obs, calls):
        t, c = time.perf_counter(), time.thread_time()
        for _ in range(calls):
            fn(obs)
        n = calls * len(obs)
        return np.array([n / (time.perf_counter() - t), n / max(time.thread_time() - c, 1e-9)])

    print("%-32s %5s %12s %12s %8s %12s %12s %8s" % ("decoder", "batch", "C++ fps", "PyTorch fps", "C++/Py",
                                                     "C++ fps/CPU", "Py fps/CPU", "C++/Py"))
    with tempfile.TemporaryDirectory() as tmp:
        for label, cpp, ref in decoders(models, tmp):
            for batch in batches:
                obs = observations(rng, batch, ref.np, 20.0)
                calls = max(1, frames // batch)
                for fn in (cpp, ref):  # warm-up
                    for _ in range(min(calls, 3)):
                        fn(obs)
                c, p = np.zeros(2), np.zeros(2)
                for _ in range(repeat):
                    c = np.maximum(c, rate(cpp, obs, calls))
                    p = np.maximum(p, rate(ref, obs, calls))
                print("%-32s %5d %12.0f %12.0f %7.2fx %12.0f %12.0f %7.2fx"
                      % (label, batch, c[0], p[0], c[0] / p[0], c[1], p[1], c[1] / p[1]))
    print("(best of %d runs of max(1, %d // batch) batch calls each, C++ and PyTorch interleaved; "
          "torch %s, %d intra-op thread; fps/CPU: per CPU second of the calling thread)"
          % (repeat, frames, torch.__version__, torch.get_num_threads()))
    return 0


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    default_models = os.path.join(os.environ.get("SEMS_SOURCE_DIR", os.path.join(here, "..", "..")), "models")
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=("check", "bench"))
    ap.add_argument("--models", default=default_models, help="the bundles' directory")
    ap.add_argument("--classifier", help="check: this classifier bundle instead of MODELS/classifier")
    ap.add_argument("--batches", default="1,32,256")
    ap.add_argument("--frames", type=int, default=2048, help="frames per timed run (bench)")
    ap.add_argument("--repeat", type=int, default=5, help="timed runs per row; the best counts (bench)")
    a = ap.parse_args()
    if a.mode == "check":
        return check(a.models, a.classifier)
    return bench(a.models, [int(b) for b in a.batches.split(",")], a.frames, a.repeat)


if __name__ == "__main__":
    sys.exit(main())
