// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: scene JSON -> channel_model -> frames (the frequency-domain emulator).
 * Input: 8 bytes of frame, seed and SNR, then the scene (fuzz/scene_input.h). A scene the
 * module refuses throws std::invalid_argument; one it accepts must give, per frame, what
 * check_realization() states, a finite H bounded by Σ|α_l| (every other factor has unit
 * modulus; float rounding allowed for),
 * |H| = 1 exactly when the frame has one path and no fading, and finite noisy values. Over
 * 256 frames of a Rayleigh scene, H at one resource element is CN(0, 1) given the paths,
 * so the mean of |H|² is a Gamma(256)/256 draw: it must lie in [0.6, 1.55] (the Chernoff
 * bound puts a false alarm below 1e-11 per input). The noise's mean power over 4096
 * values must lie within [0.88, 1.12] of σ² (below 1e-12). */
#include "scene_input.h"
#include <limits>
#include <stdexcept>

using namespace sems_fuzz;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const auto in = scene_input::split(data, size);
    const frame_settings& fs = in.fs;
    try {
        const scene sc = in.read();
        gr::sems::channel_model model(fs, sc, in.seed);
        const int n = fs.n_symbols, m = fs.n_subcarriers;
        const size_t grid = static_cast<size_t>(fs.grid_size());
        std::vector<gr_complex> h(grid);

        // Three frames in full (their grid, the noise on it).
        frame_realization r;
        for (uint64_t f = 0; f < 3; ++f) {
            model.draw(f, r);
            check_realization(fs, sc, r, f);
            // float sums over L paths: allow L float roundings of the bound
            // (a scatterer body's return is a sum of its scatterers: only finiteness is checked there)
            const double bound = r.bodies.empty() ? gain_sum(r.paths) * (1.0 + 1e-6 + 2.4e-7 * r.paths.size())
                                                  : std::numeric_limits<double>::infinity();
            if (double(r.paths.size()) * (n + m) + double(r.paths.size()) * grid > max_work)
                break; // a frame this large is checked above, its grid is not computed
            const auto fc = model.factors(r, f * static_cast<uint64_t>(n));
            fc.fill(h.data());
            const bool unit = r.paths.size() == 1 && r.bodies.empty() && sc.fading() == gr::sems::fading_kind::none;
            for (size_t i = 0; i < grid; ++i) {
                const double a = std::abs(std::complex<double>(h[i]));
                if (!std::isfinite(a))
                    fail("frame %llu: H[%zu] not finite", (unsigned long long)f, i);
                if (a > bound + 1e-30)
                    fail("frame %llu: |H[%zu]| = %g beyond sum |gain| = %g", (unsigned long long)f, i, a, bound);
                if (unit && !near(a, 1.0, 1e-5))
                    fail("one path, no fading: |H[%zu]| = %.9g, not 1", i, a);
            }
            note("frame %llu: %zu paths, grid %dx%d checked%s", (unsigned long long)f, r.paths.size(), n, m,
                 unit ? ", |H| = 1" : "");
            model.add_noise(h.data(), grid, in.snr_db);
            for (size_t i = 0; i < grid; ++i)
                if (!std::isfinite(h[i].real()) || !std::isfinite(h[i].imag()))
                    fail("frame %llu, SNR %g dB: a noisy value is not finite", (unsigned long long)f, in.snr_db);
        }

        // Unit mean channel power, statistically (Rayleigh) at one resource element.
        constexpr int frames = 256;
        if (sc.fading() == gr::sems::fading_kind::rayleigh &&
            double(r.paths.size()) * (m + n + 4) * frames <= max_work) {
            const int rn = static_cast<int>(in.seed % n), rm = static_cast<int>((in.seed * 7) % m);
            std::vector<gr_complex> row(m);
            double sum = 0.0;
            for (int f = 0; f < frames; ++f) {
                model.draw(3 + f, r);
                model.factors(r, (3 + f) * static_cast<uint64_t>(n)).row(rn, row.data());
                sum += std::norm(std::complex<double>(row[rm]));
            }
            const double mean = sum / frames;
            note("Rayleigh: %zu paths, mean |H[%d,%d]|^2 over %d frames %.4f", r.paths.size(), rn, rm, frames, mean);
            if (!(mean >= 0.6 && mean <= 1.55))
                fail("Rayleigh: mean |H[%d,%d]|^2 over %d frames = %g, not ~1", rn, rm, frames, mean);
        }

        // The noise's power: σ² = 10^(-SNR/10).
        const double var = gr::sems::channel_model::noise_variance(in.snr_db);
        if (var > 0.0) {
            std::vector<gr_complex> z(4096);
            model.add_noise(z.data(), z.size(), in.snr_db);
            double p = 0.0;
            for (const auto& v : z)
                p += std::norm(std::complex<double>(v));
            const double ratio = p / z.size() / var;
            note("noise at %g dB: mean power %.4f sigma^2", in.snr_db, ratio);
            if (!(ratio >= 0.88 && ratio <= 1.12))
                fail("noise at %g dB: mean power %g x sigma^2", in.snr_db, ratio);
        }
    } catch (const std::invalid_argument& e) {
        refused(e);
    }
    return 0;
}
