// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: scene JSON -> channel_model paths -> td_channel (the core of
 * target_channel_td) on a CP-OFDM sample stream. Input: 8 bytes of frame, seed and SNR,
 * then the scene (fuzz/scene_input.h); the symbol interval is raised to (M + CP)/B when
 * shorter (td_channel's one extra condition). Two consecutive frames of the stream, each
 * drawn frame checked as in fuzz_channel (check_realization), and:
 *  - every output sample is finite and |y| <= Σ|α_l| · √M (the tone sum of a unit-modulus
 *    QPSK symbol, unitary IFFT, is at most √M at any time; every phase has unit modulus);
 *  - the paths of the frame without Doppler and micro-Doppler, those whose delay lies
 *    inside the prefix (τB <= CP): the M-point FFT of each output symbol's prefix-free
 *    window equals H[n,m]·X[n,m] of the frequency-domain model (td_channel.h), within float
 *    rounding, on a stream of its own. */
#include "scene_input.h"
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <gnuradio/sems/core/channel/td_channel.h>
#include <limits>
#include <stdexcept>

using namespace sems_fuzz;

namespace {

// Random QPSK symbols (unit modulus) from a seeded xorshift.
struct qpsk {
    uint64_t state;
    explicit qpsk(uint64_t seed) : state(seed * 2654435761ULL + 1) {}
    void draw(gr_complex* x, int m)
    {
        for (int i = 0; i < m; ++i) {
            state ^= state << 13, state ^= state >> 7, state ^= state << 17;
            x[i] = gr_complex((state & 1) ? 1.0f : -1.0f, (state & 2) ? 1.0f : -1.0f) * float(M_SQRT1_2);
        }
    }
};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    auto in = scene_input::split(data, size);
    frame_settings& fs = in.fs;
    const int n = fs.n_symbols, m = fs.n_subcarriers, s = m + fs.cp_len;
    fs.symbol_interval_s = std::max(fs.symbol_interval_s, s / fs.bandwidth_hz);
    try {
        const scene sc = in.read();
        gr::sems::channel_model model(fs, sc, in.seed);
        gr::sems::td_channel td(fs);
        gr::sems::ofdm_modem o(m, fs.cp_len);
        qpsk symbols_of(in.seed);
        std::vector<gr_complex> x(m), t(s), y(s), rx(m), h(m);
        frame_realization r;
        for (uint64_t f = 0; f < 2; ++f) {
            model.draw(f, r);
            check_realization(fs, sc, r, f);
            const double per_symbol = double(r.paths.size()) * (s + m * std::log2(m + 1.0) + 1.0);
            if (per_symbol > max_work)
                return 0; // too large a frame to synthesise within the time limit
            const int symbols = std::max(1, std::min<int>(n, static_cast<int>(max_work / 2 / per_symbol)));
            const uint64_t first = f * static_cast<uint64_t>(n);

            // The frame as drawn: finite and bounded.
            // (a scatterer body's return is a sum of its scatterers: only finiteness is checked there)
            const double bound = r.bodies.empty()
                                     ? gain_sum(r.paths) * std::sqrt(double(m)) * (1.0 + 1e-4 + 2.4e-7 * r.paths.size())
                                     : std::numeric_limits<double>::infinity();
            td.set_frame(r, first);
            for (int k = 0; k < symbols; ++k) {
                symbols_of.draw(x.data(), m);
                o.modulate(x.data(), t.data());
                td.apply_symbol(k, t.data(), y.data());
                for (int i = 0; i < s; ++i) {
                    const double a = std::abs(std::complex<double>(y[i]));
                    if (!std::isfinite(a))
                        fail("frame %llu symbol %d sample %d: not finite", (unsigned long long)f, k, i);
                    if (a > bound + 1e-30)
                        fail("frame %llu symbol %d sample %d: |y| = %g beyond sum|gain|*sqrt(M) = %g",
                             (unsigned long long)f, k, i, a, bound);
                }
            }

            // Its static paths inside the prefix against the frequency-domain model.
            std::vector<channel_path> inside;
            for (auto p : r.paths)
                if (p.body < 0 && fs.delay_index(p.delay_s) <= fs.cp_len) {
                    p.doppler_hz = 0.0;
                    p.md_rate_hz = p.md_amplitude_m = p.md_phase_rad = 0.0;
                    inside.push_back(p);
                }
            if (inside.empty())
                continue;
            gr::sems::td_channel ref(fs);
            ref.set_paths(inside, first);
            const gr::sems::frame_channel fc(fs, inside, first);
            const double g = gain_sum(inside);
            double err = 0.0;
            for (int k = 0; k < symbols; ++k) {
                symbols_of.draw(x.data(), m);
                o.modulate(x.data(), t.data());
                ref.apply_symbol(k, t.data(), y.data());
                o.demodulate(y.data(), rx.data());
                fc.row(k, h.data());
                for (int i = 0; i < m; ++i)
                    err += std::norm(std::complex<double>(rx[i]) -
                                     std::complex<double>(h[i]) * std::complex<double>(x[i]));
            }
            // relative to the largest possible |H·X|² (Σ|α|)², per resource element
            const double rel = err == 0.0 ? 0.0 : std::sqrt(err / (double(symbols) * m)) / g;
            const double tol = 3e-6 * (1.0 + std::sqrt(double(inside.size())));
            note("frame %llu: %zu of %zu paths inside the prefix, %d symbols: rms error %.3g (limit %.3g)",
                 (unsigned long long)f, inside.size(), r.paths.size(), symbols, rel, tol);
            if (!(rel <= tol))
                fail("frame %llu: %zu static paths inside the prefix: the OFDM receiver's output differs from "
                     "H*X by %g (rms, relative to sum|gain|), more than %g",
                     (unsigned long long)f, inside.size(), rel, tol);
        }
    } catch (const std::invalid_argument& e) {
        refused(e);
    }
    return 0;
}
