// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: scene JSON -> channel_model -> frames (the frequency-domain emulator).
 * Input: 8 bytes of frame, seed and SNR, then the scene (fuzz/scene_input.h). A scene the
 * module refuses throws std::invalid_argument; one it accepts must give, per frame, what
 * check_realization() states, a finite H bounded by Σ|α_l| (every other factor has unit
 * modulus; float rounding allowed for),
 * |H| = 1 exactly when the frame has one path and no fading (with an array: at its last stream,
 * its element pattern's amplitude in the path's direction), and finite noisy values. Over
 * 256 frames of a Rayleigh scene, H at one resource element is Σ_l α_l·b_l with independent
 * α_l ~ CN(0, p_l) and b_l the path's own factor there (unit modulus for a point target; a
 * scatterer body's return, whose power swings with its motion: a long rotor blade flashes
 * hundreds of times its mean; a tracked scene's frames come from 256 tracks, one frame each,
 * since a track's gains may be kept or correlated). Given the b_l, Σ|H|² / Σ p_l|b_l|² is a weighted mean of
 * unit exponentials whose largest weight is 1/k; its Chernoff bounds are those of a
 * Gamma(k)/k draw (the log-MGF is convex in each weight), so it must lie within the bounds
 * that put a false alarm below 1e-11 per input: [0.62, 1.51] at k = 256 (one point path),
 * wider as a flash dominates; below k = 16 the check is left out. The noise's mean power
 * over 4096 values must lie within [0.88, 1.12] of σ² (below 1e-12). */
#include "scene_input.h"
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

using namespace sems_fuzz;

namespace {
/*! The ε with exp(−k·g(ε)) = 1e-11 for g increasing on [0, hi): the Chernoff tail of Gamma(k)/k. */
template <typename G>
double chernoff_margin(double k, G g, double hi)
{
    const double target = std::log(1e11) / k;
    double lo = 0.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (g(mid) < target ? lo : hi) = mid;
    }
    return hi;
}
} // namespace

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
        // A scene with an array: its last stream (the farthest element of a ULA), where the
        // steering phasor and the element's delay are largest; without one, the one stream.
        const int element = model.n_elements() - 1;
        auto factors = [&](const frame_realization& fr, uint64_t first) {
            return model.n_elements() > 1 ? model.factors(fr, first, element) : model.factors(fr, first);
        };

        // Three frames in full (their grid, the noise on it), and their track bookkeeping.
        frame_realization r, prev;
        for (uint64_t f = 0; f < 3; ++f) {
            model.draw(f, r);
            check_realization(fs, sc, r, f);
            check_track_step(fs, sc, f ? &prev : nullptr, r);
            prev = r;
            // float sums over L paths: allow L float roundings of the bound
            // (a scatterer body's return is a sum of its scatterers: only finiteness is checked there)
            const double bound = r.bodies.empty() ? gain_sum(r.paths) * (1.0 + 1e-6 + 2.4e-7 * r.paths.size())
                                                  : std::numeric_limits<double>::infinity();
            if (double(r.paths.size()) * (n + m) + double(r.paths.size()) * grid > max_work)
                break; // a frame this large is checked above, its grid is not computed
            const auto fc = factors(r, f * static_cast<uint64_t>(n));
            fc.fill(h.data());
            const bool unit = r.paths.size() == 1 && r.bodies.empty() && sc.fading() == gr::sems::fading_kind::none;
            // one unfaded path: |H| is its element pattern's amplitude in its direction (1 for one antenna)
            const double unit_mag = unit && sc.array() ? gr::sems::element_pattern_amplitude(
                                                             sc.array()->pattern(),
                                                             gr::sems::direction_vector(r.paths[0].azimuth_rad,
                                                                                        r.paths[0].elevation_rad))
                                                       : 1.0;
            for (size_t i = 0; i < grid; ++i) {
                const double a = std::abs(std::complex<double>(h[i]));
                if (!std::isfinite(a))
                    fail("frame %llu: H[%zu] not finite", (unsigned long long)f, i);
                if (a > bound + 1e-30)
                    fail("frame %llu: |H[%zu]| = %g beyond sum |gain| = %g", (unsigned long long)f, i, a, bound);
                if (unit && !near(a, unit_mag, 1e-5))
                    fail("one path, no fading: |H[%zu]| = %.9g, not %.9g", i, a, unit_mag);
            }
            if (unit)
                note("frame %llu: 1 path, grid %dx%d checked, |H| = %.6g", (unsigned long long)f, n, m, unit_mag);
            else
                note("frame %llu: %zu paths, grid %dx%d checked", (unsigned long long)f, r.paths.size(), n, m);
            model.add_noise(h.data(), grid, in.snr_db);
            for (size_t i = 0; i < grid; ++i)
                if (!std::isfinite(h[i].real()) || !std::isfinite(h[i].imag()))
                    fail("frame %llu, SNR %g dB: a noisy value is not finite", (unsigned long long)f, in.snr_db);
        }

        // Unit mean channel power given each path's own factor, statistically (Rayleigh), at
        // one resource element.
        constexpr int frames = 256;
        const double paths = double(r.paths.size());
        if (sc.fading() == gr::sems::fading_kind::rayleigh && paths * (paths + 1) * (m + n + 4) * frames <= max_work) {
            const int rn = static_cast<int>(in.seed % n), rm = static_cast<int>((in.seed * 7) % m);
            std::vector<gr_complex> row(m);
            double sum = 0.0, expected = 0.0, largest = 0.0;
            frame_realization one;
            for (int f = 0; f < frames; ++f) {
                const uint64_t first = (3 + f) * static_cast<uint64_t>(n);
                if (tracked(sc)) // a track's gains may be coherent: the first frame of another track each time
                    model.begin_track(1000 + static_cast<uint64_t>(f));
                model.draw(3 + f, r);
                factors(r, first).row(rn, row.data());
                sum += std::norm(std::complex<double>(row[rm]));
                one.bodies = r.bodies;
                for (const auto& p : r.paths) { // p_l·|b_l|² at this resource element
                    one.paths.assign(1, p);
                    one.paths[0].gain = 1.0;
                    factors(one, first).row(rn, row.data());
                    const double w = p.mean_power * std::norm(std::complex<double>(row[rm]));
                    expected += w;
                    largest = std::max(largest, w);
                }
            }
            const double k = largest > 0.0 ? expected / largest : 0.0;
            if (k >= 16.0) {
                const double up = chernoff_margin(k, [](double e) { return e - std::log1p(e); }, 1e3);
                const double down = chernoff_margin(k, [](double e) { return -e - std::log1p(-e); }, 1.0);
                const double ratio = sum / expected;
                note("Rayleigh: %zu paths, sum |H[%d,%d]|^2 over %d frames %.4f x its mean given the paths "
                     "(k = %.1f, bounds [%.3f, %.3f])",
                     r.paths.size(), rn, rm, frames, ratio, k, 1.0 - down, 1.0 + up);
                if (!(ratio >= 1.0 - down && ratio <= 1.0 + up))
                    fail("Rayleigh: sum |H[%d,%d]|^2 over %d frames = %g x its mean given the paths "
                         "(k = %.1f), outside [%g, %g]",
                         rn, rm, frames, ratio, k, 1.0 - down, 1.0 + up);
            } else {
                note("Rayleigh: k = %.1f (one frame's flash dominates), power check left out", k);
            }
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
