// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model at sample level (docs/design.md §3, time domain).
 *
 * The same paths as the frequency-domain model (channel_model::draw), applied to a
 * CP-OFDM sample stream: symbols of S = M + CP samples back to back in the stream.
 *
 * Time. Symbol s (absolute, s = frame·N + n) starts at slow time s·T, and its sample k
 * (k = 0 .. S-1, cyclic prefix included) lies at t = s·T + k/B. The stream carries no
 * gap between symbols: T only clocks the phases (T ≥ S/B is required, the symbol must
 * fit its interval), while the delay acts on the contiguous stream, so a delay past
 * the CP reaches into the previous symbol of the stream (ISI).
 *
 * Per path l and output sample p (symbol s, sample k):
 *
 *     y[p] = Σ_l α_l · exp(j2π ν_l t) · exp(j (4π/λ) A_l sin(ω_l t + φ_l)) · x_c(p/B − τ_l)
 *
 * evaluated at the RECEIVE time t = s·T + k/B, with the paths of the frame that holds p.
 *
 * x_c is the transmitted waveform between samples: within each symbol the sum of its M
 * tones at frequencies m·Δf (m = 0..M-1, the frequencies of the frequency-domain
 * model), switching at symbol boundaries. A delay τ·B = D + δ (D integer, 0 ≤ δ < 1) is
 * a shift by D samples of the stream and, per symbol, a fractional shift by δ applied in
 * the frequency domain (FFT of the symbol's last M samples, · exp(-j2π m δ/M), inverse
 * FFT). Error: none beyond float rounding for a CP-OFDM input (the tone sums are
 * exact), so with τ·B ≤ CP, no Doppler, the M-point FFT of the prefix-free window equals
 * H[n,m]·X[n,m] of the frequency-domain model (measured: ~1e-7 relative, qa). Input that
 * is not CP-OFDM with these M and CP is interpolated as if it were.
 *
 * Doppler phases are exact per sample: a per-frame table exp(j2π ν k/B) (double, anchored
 * every 64 samples) times the symbol's phase exp(j2π ν s T) (a per-frame table: the
 * frame's first symbol reduced modulo one cycle in double, the others by recurrence in
 * double, anchored every 64 symbols). Micro-Doppler phases are exact (double, ~1e-15 rad) at
 * the start of each chunk of samples and linear inside it (a float rotator, as VOLK's), the
 * chunk K chosen so the curvature left out, β·ω²·(K/B)²/8 with β = 4πA/λ, stays below 1e-7
 * rad.
 *
 * Range migration within a frame is not modelled (the delay is fixed per frame), as in
 * the frequency-domain model.
 */
#ifndef INCLUDED_SEMS_CORE_TD_CHANNEL_H
#define INCLUDED_SEMS_CORE_TD_CHANNEL_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/channel_model.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <cstdint>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Per-sample synthesis of one frame's paths on a CP-OFDM sample stream.
 *
 * Keeps the previous symbol of the stream (for delays that reach across a symbol
 * boundary); starts from silence. Allocation-free per symbol once the buffers have
 * grown to the scene's path count.
 */
class SEMS_API td_channel
{
public:
    /*!
     * \brief A sample-level channel for a frame format.
     * \param fs frame settings; uses M, cp_len, B, T, f_c.
     * \throws std::invalid_argument when T < (M + cp_len)/B (a symbol longer than its interval).
     */
    explicit td_channel(const frame_settings& fs);
    ~td_channel(); ///< Destructor.
    /*! \brief Move constructor. */
    td_channel(td_channel&&) noexcept;
    /*! \brief Move assignment. \return *this. */
    td_channel& operator=(td_channel&&) noexcept;

    //! \brief Samples per symbol, S = M + cp_len. \return S.
    int symbol_len() const { return d_s; }
    //! \brief The frame. \return the frame settings.
    const frame_settings& settings() const { return d_fs; }

    /*!
     * \brief The paths of the next symbols (a new frame).
     * \param paths a frame's paths (channel_model::draw); delays must lie in [0, 1/Δf)
     * \param first_symbol absolute slow-time index of the frame's first symbol
     */
    void set_paths(const std::vector<channel_path>& paths, uint64_t first_symbol);

    /*!
     * \brief The next symbol of the stream: S samples in, S samples out (noiseless).
     * \param n symbol index within the frame (slow time first_symbol + n)
     * \param in the S transmitted samples
     * \param out the S received samples (may not alias in)
     * \throws std::out_of_range when n is not in 0..N-1
     */
    void apply_symbol(int n, const gr_complex* in, gr_complex* out);

    //! Forget the stream's history (the previous symbol becomes silence).
    void reset();

private:
    struct impl;
    frame_settings d_fs;
    int d_s;
    std::unique_ptr<impl> d;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_TD_CHANNEL_H */
