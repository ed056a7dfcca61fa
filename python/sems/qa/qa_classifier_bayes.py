#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""docs/results/classifier_bayes.py on a scene of bodies (--scene): the likelihood of
y = alpha g + v against the Gaussian density written out in full, the chunked Monte-Carlo
class posterior against the same mean computed at once, and the scenes it refuses; and
docs/results/bank_likelihoods.py's likelihood without a known scale against that density
integrated over the scale."""
import importlib.util
import json
import os
import tempfile

import numpy as np
from gnuradio import gr_unittest, sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
SCENE = os.path.join(SOURCE, "models", "scenes", "kinematic_any.json")


def load_script(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join(SOURCE, "docs", "results", name + ".py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


cb = load_script("classifier_bayes")
bl = load_script("bank_likelihoods")


def complex_normal_logpdf(y, cov):
    """log CN(y; 0, cov), written out: -N log(pi) - log det cov - y^H cov^-1 y."""
    _, logdet = np.linalg.slogdet(cov)
    return -len(y) * np.log(np.pi) - logdet - np.real(y.conj() @ np.linalg.solve(cov, y))


def log_mean_exp(a, axis):
    top = a.max(axis, keepdims=True)
    return np.squeeze(top, axis) + np.log(np.mean(np.exp(a - top), axis))


class qa_classifier_bayes(gr_unittest.TestCase):

    def test_likelihood_against_the_full_density(self):
        # log p(y | theta) up to a term common to every theta: the difference to the full
        # complex Gaussian density of covariance s2 I + g g^H is one constant per frame.
        rng = np.random.default_rng(1)
        n_p, k = 4, 6
        scale = rng.uniform(0.1, 3.0, (k, 1))  # bodies: |g|^2 varies from draw to draw
        sig = ((rng.standard_normal((k, n_p)) + 1j * rng.standard_normal((k, n_p))) * scale).astype(np.complex64)
        y = ((rng.standard_normal((3, n_p)) + 1j * rng.standard_normal((3, n_p))) * 2).astype(np.complex64)
        for s2 in (0.05, 1.0, 20.0):
            ll = cb.body_loglik(y, sig, s2)
            ref = np.array([[complex_normal_logpdf(y[t].astype(complex),
                                                   s2 * np.eye(n_p) + np.outer(sig[j], sig[j].conj()))
                             for j in range(k)] for t in range(3)])
            d = ref - ll
            spread = np.ptp(d, axis=1).max()
            self.assertLess(spread, 1e-4 * max(1.0, np.abs(ll).max()), "s2 %g: %s" % (s2, d))
            # the dropped terms are exactly -N_p log(pi s2) - |y|^2 / s2
            common = -n_p * np.log(np.pi * s2) - np.sum(np.abs(y.astype(complex)) ** 2, 1) / s2
            np.testing.assert_allclose(d[:, 0], common, rtol=1e-5, atol=1e-3)
        # unit-modulus signatures: the determinant term is common, and the ordering is the
        # paper's exp(|g^H y|^2 / (s2 (s2 + N_p)))
        g = np.exp(1j * rng.uniform(0, 2 * np.pi, (k, n_p))).astype(np.complex64)
        ll = cb.body_loglik(y, g, 0.5)
        paper = np.abs(y @ g.conj().T) ** 2 / (0.5 * (0.5 + n_p))
        self.assertLess(np.ptp(ll - paper, axis=1).max(), 1e-4)

    def test_chunked_posterior_equals_the_mean_at_once(self):
        # A tiny kinematic case: 40 test frames, 90 prior draws in chunks of 16 (the half
        # boundary inside a chunk), test tiles of 8 frames; decisions equal the Monte-Carlo
        # mean computed over all draws at once, at two SNRs and noiseless.
        fs = sems.frame_settings()
        sc, unit = cb.load_scene(sems, SCENE)
        names = [sc.class_name(c) for c in sc.label_classes()]
        self.assertEqual(names, ["adult", "child", "quadcopter", "hexacopter", "car", "bicyclist"])
        idx = [np.array(sems.pilot_mask.from_pattern("doppler", fs.n_symbols, fs.n_subcarriers, 8, 1).flat_indices())]
        clean, t_cls, gain = cb.draw_scene_test(sems, sc, fs, idx, names, 40, 7)
        self.assertTrue(np.all(gain > 0))
        rng = np.random.default_rng(3)
        noise = [((rng.standard_normal((40, 8)) + 1j * rng.standard_normal((40, 8))) / np.sqrt(2)).astype(np.complex64)]
        s2s = [10 ** 0.5, 0.1, 0.0]
        n_prior = 90
        dec, per_cls = cb.bayes_scene(sems, unit, fs, idx, names, clean, noise, s2s, n_prior, 8, chunk=16, cells=16 * 8)
        self.assertEqual(per_cls.sum(), n_prior)

        # the same draws at once: the unit-gain scene's frames have |alpha| = 1
        model = sems.channel_model(fs, unit, 8)
        h, truths = model.generate(n_prior, 0)
        sig = np.asarray(h).reshape(n_prior, -1)[:, idx[0]]
        cls = np.array([names.index(t["class_name"]) for t in truths])
        np.testing.assert_array_equal(np.bincount(cls, minlength=len(names)), per_cls)
        r = sems.channel_model(fs, unit, 8).draw(0)
        self.assertEqual(r.paths[0].gain, 1)
        for s2 in s2s:
            y = clean[0] + np.float32(np.sqrt(s2)) * noise[0]
            ll = cb.body_loglik(y, sig, s2).astype(np.float64)
            for name, draws in (("full", np.arange(n_prior)), ("half", np.arange(n_prior // 2))):
                score = np.full((40, len(names)), -np.inf)
                for c in range(len(names)):
                    sel = draws[cls[draws] == c]
                    if len(sel):
                        score[:, c] = ll[:, sel].max(1) if s2 == 0 else log_mean_exp(ll[:, sel], 1)
                got = dec[(0, s2)][0 if name == "full" else 1]
                # equal decisions, except where two classes' scores tie to float rounding
                top2 = np.sort(score, 1)[:, -2:]
                clear = top2[:, 1] - top2[:, 0] > 1e-4
                self.assertGreater(clear.sum(), 30)
                np.testing.assert_array_equal(got[clear], score.argmax(1)[clear], "s2 %g, %s" % (s2, name))

    def test_scenes_it_refuses(self):
        # The model is one target, one path, a Rayleigh gain: anything else is refused and
        # the error names the file and what is wrong.
        with open(SCENE) as f:
            base = json.load(f)
        cases = [({"fading": "none"}, "fading"),
                 ({"random": {"heading": "any", "paths_per_target": 3}}, "paths per target"),
                 ({"random": {"heading": "any", "targets": 2}}, "targets"),
                 ({"clutter": {"csr_db": 10}}, "clutter")]
        with tempfile.TemporaryDirectory() as tmp:
            for change, words in cases:
                d = dict(base, **change)
                path = os.path.join(tmp, "bad.json")
                with open(path, "w") as f:
                    json.dump(d, f)
                with self.assertRaises(ValueError) as ctx:
                    cb.load_scene(sems, path)
                self.assertIn(path, str(ctx.exception))
                self.assertIn(words, str(ctx.exception))

    def test_csv_keeps_the_bound_beside_decoders_of_a_prior_size(self):
        # A --csv file holds the bound and the decoders of given prior sizes (--as-decoder) for
        # one mask: a run replaces only the rows of its own kind, and size.
        def rows(method, acc):
            return [dict(experiment=1, scenario="kinematic_any", method=method, mask="doppler", n_pilots=32,
                         snr_db="0", accuracy=acc, macro_f1=acc, n_frames=3000, seed=1, train_seed="none",
                         us_per_frame="1", train_seconds=0, model="m")]
        small, large = cb.METHOD_DRAWS % "30 000", cb.METHOD_DRAWS % "300 000"
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "bound.csv")
            cb.write_csv(path, "kinematic_any", rows(cb.METHOD, "0.47"))
            cb.write_csv(path, "kinematic_any", rows(small, "0.45"))
            cb.write_csv(path, "kinematic_any", rows(large, "0.46"))
            cb.write_csv(path, "kinematic_any", rows(small, "0.44"))  # the same size again: replaced
            cb.write_csv(path, "kinematic_any", rows(cb.METHOD_UNCONVERGED, "0.48"))  # the bound again
            with open(path) as f:
                got = sorted((r["method"], r["accuracy"]) for r in cb.csv.DictReader(f))
        self.assertEqual(got, sorted([(small, "0.44"), (large, "0.46"), (cb.METHOD_UNCONVERGED, "0.48")]))


    def test_scale_free_likelihood_is_the_density_integrated_over_the_scale(self):
        # y = c (alpha g + v): the density of y given g and s2, integrated over log c (the prior
        # 1/c) by quadrature, differs from bank_likelihoods' closed form by one constant per
        # frame, the same for every template and noise level; and the closed form does not
        # change when the frame is scaled.
        rng = np.random.default_rng(3)
        n_p, k = 5, 4
        t = rng.standard_normal((k, n_p)) + 1j * rng.standard_normal((k, n_p))
        t /= np.linalg.norm(t, axis=1, keepdims=True)
        e = 2.5
        y = t[1] * 1.3 + 0.4 * (rng.standard_normal(n_p) + 1j * rng.standard_normal(n_p))
        log_c = np.linspace(-12.0, 12.0, 24001)
        diffs = []
        for s2 in (0.05, 0.5, 4.0):
            for j in range(k):
                g = np.sqrt(e) * t[j]
                cov = s2 * np.eye(n_p) + np.outer(g, g.conj())
                dens = np.array([complex_normal_logpdf(y, np.exp(2 * u) * cov) for u in log_c])
                integral = log_mean_exp(dens, 0) + np.log(log_c[-1] - log_c[0])  # ∫ p(y | c) dc/c, dc/c = d log c
                rho = np.abs(t[j].conj() @ y) ** 2 / np.sum(np.abs(y) ** 2)
                diffs.append(integral - float(bl.scale_free_loglik(np.float32(rho), e, s2, n_p)))
                for scale in (1e-3, 1e3):
                    rho_s = np.abs(t[j].conj() @ (scale * y)) ** 2 / np.sum(np.abs(scale * y) ** 2)
                    self.assertAlmostEqual(float(bl.scale_free_loglik(np.float32(rho_s), e, s2, n_p)),
                                           float(bl.scale_free_loglik(np.float32(rho), e, s2, n_p)), places=3)
        self.assertLess(np.ptp(diffs), 1e-3, diffs)
        # the constant is the dropped terms, -N_p log |y|^2 + log(Γ(N_p) / 2) - N_p log π (with
        # w = 1/c², dc/c = dw/(2w) and ∫ w^(N_p - 1) exp(-w Q) dw = Γ(N_p) / Q^N_p)
        from math import lgamma
        want = -n_p * np.log(np.sum(np.abs(y) ** 2)) + lgamma(n_p) - np.log(2.0) - n_p * np.log(np.pi)
        self.assertAlmostEqual(float(np.mean(diffs)), want, places=3)


if __name__ == "__main__":
    gr_unittest.run(qa_classifier_bayes)
