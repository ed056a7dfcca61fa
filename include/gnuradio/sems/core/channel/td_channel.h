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
 * One transmitted symbol's echo keeps one slow time: a path delayed by D whole samples puts
 * the last D samples of symbol s − 1's echo at the start of symbol s, and there its Doppler
 * and micro-Doppler phases continue symbol s − 1's, t = (s − 1)·T + (S + k)/B. (Taken at
 * s·T + k/B instead, those samples, which a receiver's FFT window never holds for D ≤ CP,
 * would turn by 2πν(T − S/B) against the prefix they repeat, and a cyclic-prefix estimator
 * such as cp_sync would read ν·T subcarrier spacings of frequency offset.) A scatterer body's
 * expansion terms G_p(t) are still interpolated at s·T + k/B there.
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
 * Scatterer bodies (rotors, walkers, wheels, point scatterers: channel_path::body) are the
 * frequency-domain model's separable expansion (lib/core/channel/scatterer_moments.h): a body path is
 * Σ_{band,p} δk_m^p · G_p(t), and each term is a path of its own whose subcarrier factor
 * (δk_m/δk_max)^p on its sub-band (0 elsewhere) is applied per symbol in the frequency domain
 * with the fractional delay, and whose slow-time factor G_p(t)·δk_max^p multiplies its
 * samples together with the path's Doppler. The displacements of the scatterers are thus
 * applied within the symbol like δ: with τ + 2·extent/c within the prefix the prefix-free
 * window holds them exactly. G is evaluated exactly (double) at anchors spread evenly over
 * each symbol, the first at k = 0 (the frequency-domain model's t_n), the last at k = S, and
 * interpolated between them (Lagrange, degree d = 1, 2 or 3 over d + 1 anchors h samples
 * apart; a still body: one anchor). The subcarrier's response h_m(t) = Σ_s a_s e^{-jκ_m r_s(t)}
 * is interpolated the same way (it is linear in the G_p), so the error is at most
 * |h_m^(d+1)|·C_d·(h/B)^(d+1)/(d+1)! with C_d = 1/4, 2/(3√3), 1, and
 * |h_m^(n)| ≤ Σ_s|a_s|·(κv + 2ω)^n (n ≤ 4), κ the top subcarrier's wavenumber, v the
 * body's peak scatterer speed (micro_motion_peak_speed_mps) and ω its fastest angular rate
 * (rotors 2πf, wheels v/R, harmonics 2πf, walkers the gait cycle's 8th harmonic; κv
 * dominates). The degree and spacing needing the fewest anchors that keep this below 1e-6 of
 * a unit-power target are used. At 3 GHz, 30 MHz, M 64, CP 16: a 100 rev/s quadcopter
 * (blade tips 80 m/s) takes 3 anchors per symbol (quadratic), and a 1.8 m walker at 1.4 m/s
 * 3 anchors too (linear over two segments). Evaluating
 * G once per symbol instead would leave a phase change of κ·v·S/B ≈ 0.03 rad across a fast
 * rotor's symbol. qa_td_channel checks the return against a direct per-sample sum over the
 * scatterers: within 1e-6 plus the float rounding of the terms (each at most Σ|a|·x^p/p!,
 * x = δk_max·extent: ~6e-6 at the band edge for a car's wheels, as in the frequency-domain
 * model). Cost: evaluating the anchors (a body's snapshot and moments) dominates.
 *
 * The frequency-domain model evaluates a body once per symbol (at t_n), this emulator per
 * sample: in the M-point FFT of the prefix-free window the two differ by the motion within
 * the symbol, relative to |α|²·‖X‖² at most (Σ|a_s|·κ·v·(S−1)/B)² in power (first order
 * in the displacement; measured: a 2 rev/s quadcopter 6e-9 against a bound of 5e-6, a
 * 100 rev/s one 2e-5 against 1e-2).
 *
 * Range migration within a frame is not modelled (the delay is fixed per frame), as in
 * the frequency-domain model.
 */
#ifndef INCLUDED_SEMS_CORE_TD_CHANNEL_H
#define INCLUDED_SEMS_CORE_TD_CHANNEL_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
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
     * \throws std::invalid_argument for an invalid frame (frame_settings::validate) or when
     *         T < (M + cp_len)/B (a symbol longer than its interval).
     */
    explicit td_channel(const frame_settings& fs);
    /*!
     * \brief The same at one element of an array (channel_model::elements()): every path turned
     *        by its steering phasor and moved by the plane wave's exact delay at the element
     *        (within the fractional delay, so wide apertures and bands stay exact), each body's
     *        scatterers from their own directions, as frame_channel does at that element.
     * \param fs frame settings. \param element the element (the origin: the single antenna).
     * \throws std::invalid_argument as above.
     */
    td_channel(const frame_settings& fs, const array_element& element);
    /*! \brief The element the samples are computed for. \return it (the origin by default). */
    const array_element& element() const { return d_element; }
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
     * \brief The point paths of the next symbols (a new frame).
     * \param paths a frame's paths (channel_model::draw); delays must lie in [0, 1/Δf)
     * \param first_symbol absolute slow-time index of the frame's first symbol
     * \throws std::invalid_argument when a path refers to a scatterer body (use set_frame) or
     *         its delay is outside [0, 1/Δf)
     */
    void set_paths(const std::vector<channel_path>& paths, uint64_t first_symbol);

    /*!
     * \brief A drawn frame for the next symbols: its paths and scatterer bodies.
     * \details A body's models are kept while its parameters stay (fixed scenes set them up
     * once); allocation-free per symbol once the buffers have grown to the scene's terms.
     * \param r a drawn frame (channel_model::draw); delays must lie in [0, 1/Δf)
     * \param first_symbol absolute slow-time index of the frame's first symbol (a frame with its own clock, frame_realization::clock_symbol, uses that)
     * \throws std::invalid_argument when a path refers to a body the frame does not have or
     *         its delay is outside [0, 1/Δf)
     */
    void set_frame(const frame_realization& r, uint64_t first_symbol);

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
    void set_paths(const std::vector<channel_path>& paths, const std::vector<scatterer_body>* bodies, uint64_t first_symbol);
    struct impl;
    frame_settings d_fs;
    array_element d_element;
    int d_s;
    std::unique_ptr<impl> d;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_TD_CHANNEL_H */
