// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: THE channel model (DESIGN §1). The emulator block, the training app, the
 * evaluation and the Python bindings all draw their channels here.
 *
 *   H[n,m] = Σ_l α_l · exp(-j2π m Δf τ_l) · exp(j2π ν_l t_n) · exp(j (4π/λ) A_l sin(ω_l t_n + φ_l))
 *   Y[n,m] = H[n,m] · X[n,m] + V[n,m],   V ~ CN(0, σ²),  σ² = 10^(-SNR/10)
 *
 * H is separable per path: a delay factor over m times a slow-time factor over n,
 * so a frame costs L·(N + M) phase evaluations plus the N·M accumulation, and the
 * micro-Doppler factor is only evaluated for paths that have one.
 * t_n is absolute slow time (symbol index since the stream began, times T): phases
 * are reduced modulo one cycle in double precision, so a fixed scene keeps a
 * continuous, drift-free Doppler phase however long it streams.
 *
 * Draws are seeded and reproducible. Scene/gain draws and noise draws use separate
 * generators, so the same seed gives the same frames at every SNR.
 */
#ifndef INCLUDED_SEMS_CORE_CHANNEL_MODEL_H
#define INCLUDED_SEMS_CORE_CHANNEL_MODEL_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <gnuradio/sems/core/scene.h>
#include <complex>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {

// One propagation path of one frame, with its gain already drawn.
struct SEMS_API channel_path {
    double delay_s = 0.0;
    double doppler_hz = 0.0;
    double md_rate_hz = 0.0;      // 0: no micro-Doppler factor
    double md_amplitude_m = 0.0;
    double md_phase_rad = 0.0;
    std::complex<double> gain{ 1.0, 0.0 }; // α_l
    double mean_power = 1.0;               // p_l
};

// Ground truth of one frame: the target of interest (its direct path).
struct SEMS_API frame_truth {
    uint64_t frame = 0;
    int class_id = 0;
    std::string class_name;
    double delay_s = 0.0;
    double delay_index = 0.0; // τ·B
    double range_m = 0.0;
    double velocity_mps = 0.0;
    double snr_db = 0.0;      // +inf when noiseless
    int n_paths = 0;          // all paths of the realization, clutter included
};

struct SEMS_API frame_realization {
    std::vector<channel_path> paths;
    frame_truth truth;
};

// The separable factors of one frame: H[n,m] = Σ_l slow_l[n] · delay_l[m].
class SEMS_API frame_channel
{
public:
    frame_channel(const frame_settings& fs, const std::vector<channel_path>& paths, uint64_t first_symbol);
    // The factors of another frame, computed in place in the same buffers: what a
    // streaming block calls once per frame, allocation-free once the buffers have grown.
    void update(const std::vector<channel_path>& paths, uint64_t first_symbol);

    int n_symbols() const { return d_n; }
    int n_subcarriers() const { return d_m; }
    int n_paths() const { return d_l; }

    void row(int n, gr_complex* h) const;                              // h[m] = H[n,m]
    void apply_row(int n, const gr_complex* x, gr_complex* y) const;   // y = H[n,:] ⊙ x
    void fill(gr_complex* grid) const;                                 // row-major N x M

private:
    frame_settings d_fs;
    int d_n, d_m, d_l;
    std::vector<gr_complex> d_slow;  // L x N, gain included
    std::vector<gr_complex> d_delay; // L x M
    std::vector<gr_complex> d_delay_conj; // conj(d_delay), for VOLK's multiply-conjugate-add
    std::vector<double> d_delay_s;        // the delay each delay row was computed for
    mutable std::vector<gr_complex> d_scratch;
};

class SEMS_API channel_model
{
public:
    // Validates the scene against the frame (ranges inside the unambiguous delay,
    // instantaneous Doppler inside ±1/(2T)); throws std::invalid_argument.
    channel_model(const frame_settings& fs, const scene& sc, uint64_t seed);
    ~channel_model();
    channel_model(channel_model&&) noexcept;
    channel_model& operator=(channel_model&&) noexcept;

    const frame_settings& settings() const { return d_fs; }
    const scene& scene_spec() const { return d_scene; }

    // σ² for an SNR in dB; 0 for +inf. Throws on NaN.
    static double noise_variance(double snr_db);

    // Draw the next frame's paths (scene parameters for random scenes, and gains).
    frame_realization draw(uint64_t frame_index);
    // The same draw into `out`, reusing its buffers: what a streaming block calls once
    // per frame, allocation-free once they have grown (fixed scenes are read in place).
    void draw(uint64_t frame_index, frame_realization& out);
    // The frame's factors; first_symbol is the absolute slow-time index of row 0.
    frame_channel factors(const frame_realization& r, uint64_t first_symbol) const;

    // y += CN(0, σ²) per element; draws nothing when snr_db = +inf. The noise is a
    // single-precision vectorised Box–Muller stream (lib/core/gaussian_generator.h):
    // the same seed gives the same noise whatever the sizes of the calls.
    void add_noise(gr_complex* y, size_t count, double snr_db);

    // `count` consecutive frames starting at frame `first_frame` (rows at
    // first_frame·N): noiseless H into h_out (count x N x M), truths returned.
    std::vector<frame_truth> generate(size_t count, gr_complex* h_out, uint64_t first_frame = 0);

    void reseed(uint64_t seed);

private:
    struct rngs; // generators and per-frame scratch (lib/core/channel_model.cc)
    frame_settings d_fs;
    scene d_scene;
    std::unique_ptr<rngs> d_rng;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_CHANNEL_MODEL_H */
