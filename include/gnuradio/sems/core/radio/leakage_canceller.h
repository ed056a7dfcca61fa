// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: cancels the transmitter's leakage into a monostatic radio's receiver.
 *
 * A monostatic SDR receives its own transmission straight from the TX port, 40 dB or more
 * above the echoes: a static path at delay ~0 with a few samples of delay spread. The
 * receiver's IQ imbalance adds a mirrored image of it (conj of the leakage, on the mirrored
 * subcarriers), and its mixer a DC offset. The radio knows what it sent, so the canceller
 * fits the widely-linear static model
 *
 *     rx[n] ≈ Σ_{d=0}^{L−1} h_d·tx[n−d] + g_d·conj(tx[n−d]) + c
 *
 * (K = 2L + 1 regressors; L without the image, no c without DC) by least squares and
 * subtracts it from rx. The fit is per window of W samples (best: one frame), a posteriori
 * (the window's own estimate is subtracted from it), with exponential forgetting across
 * windows: R_k = λ·R_{k−1} + Σ_window φ*·φᵀ, p_k = λ·p_{k−1} + Σ_window φ*·rx, w_k = R_k⁻¹p_k.
 * The leakage does not change between frames, an echo of a moving target turns its phase
 * (Doppler) and moves: averaged over 1/(1 − λ) windows it falls out of the fit, while the
 * leakage's estimate gains (1 + λ)/(1 − λ) in noise.
 *
 * Cost and accuracy: per sample about 2·L complex multiply-adds for the normal matrix (its
 * entries are lagged products of tx, summed once per lag), K for the right side and K for the
 * subtraction, plus K²/2 per clipped sample and one K×K solve per window. With
 * white noise of variance σ² the residual leakage left in the output (the fit's error) has
 * power σ²·K/W per sample at λ = 0 and σ²·K·(1 − λ)/((1 + λ)·W) in the steady state.
 *
 * What it removes: every component of rx that is a fixed widely-linear filter of the last L
 * transmitted samples over the averaging window — the leakage, its IQ image, the DC offset,
 * and equally any echo or clutter within the first L samples of delay that does not move
 * over the window (a target there is indistinguishable from leakage). What it cannot: an
 * echo delayed by L samples or more passes (it is not in the regressors; only its chance
 * correlation with them, a fraction ≈ K/W of its power at λ = 0, is lost); leakage with a
 * longer delay spread than L samples, or that changes within the window (a drifting
 * oscillator, a nonlinear amplifier), is left in part. tx and rx must be sample-aligned (the
 * radio's fixed TX-to-RX latency removed upstream).
 *
 * Clipped samples. When the converter clips, it clips where the leakage peaks, and a clipped
 * rail has lost the leakage's overshoot beyond full scale: subtracting the fit there leaves
 * an error of the leakage's size, tens of dB above the echo, in one sample that the receiver's
 * FFT spreads over every subcarrier of its symbol. Given the converter's full scale (the
 * largest magnitude a rail takes), the canceller leaves clipped samples out of the fit and
 * bounds their residual by what the clipped rail still says: a rail at +full scale only says
 * that the echo there is at least full scale minus the fitted leakage, so the residual is
 * kept when positive and set to 0 otherwise (mirrored at −full scale). The clipped rail's
 * error then falls from the leakage's overshoot to at most the echo's own size.
 */
#ifndef INCLUDED_SEMS_CORE_LEAKAGE_CANCELLER_H
#define INCLUDED_SEMS_CORE_LEAKAGE_CANCELLER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstddef>
#include <vector>

namespace gr {
namespace sems {

//! \brief The canceller's settings (defaults: one frame of the default frame settings).
struct SEMS_API leakage_canceller_settings {
    int taps = 4;               //!< L, the leakage's delay spread in samples (1 .. 64)
    //! W, samples per fit (>= 2·K): one frame N·(M + CP) of the default frame settings
    int window = frame_settings{}.n_symbols * (frame_settings{}.n_subcarriers + frame_settings{}.cp_len);
    double forgetting = 0.9;    //!< λ in [0, 1): weight of the previous windows' fit
    bool widely_linear = true;  //!< fit the IQ image (conj(tx) taps) too
    bool dc = true;             //!< fit a DC offset too
    //! The converter's full scale per rail in the stream's units (the largest |I| or |Q| it
    //! outputs, e.g. 32767/32768 for UHD's sc16 samples as fc32); 0: no clipping handled
    double clip_level = 0.0;

    //! \brief Refuses bad values. \throws std::invalid_argument naming the parameter.
    void validate() const;
    //! \brief K, the number of regressors. \return L·(1 + widely_linear) + dc.
    int regressors() const { return taps * (widely_linear ? 2 : 1) + (dc ? 1 : 0); }
};

/*!
 * \brief Least-squares widely-linear canceller of the transmitter's leakage, its IQ image
 *        and the DC offset (see the file comment for the model and its limits); the
 *        block sems::leakage_canceller streams it.
 */
class SEMS_API leakage_fit
{
public:
    /*!
     * \param settings the settings
     * \throws std::invalid_argument naming the bad parameter.
     */
    explicit leakage_fit(const leakage_canceller_settings& settings = {});

    /*!
     * \brief Cancels one window: fits the model on it (with the forgetting), subtracts the fit.
     * \param rx  window() received samples
     * \param tx  window() transmitted samples, aligned with rx (the L − 1 before the window
     *            are kept from the previous call; zeros before the first)
     * \param out window() samples, rx minus the fitted leakage (may be rx itself)
     */
    void process(const gr_complex* rx, const gr_complex* tx, gr_complex* out);

    //! \brief Samples per call of process(). \return W.
    int window() const { return d_set.window; }
    //! \brief The settings. \return them.
    const leakage_canceller_settings& settings() const { return d_set; }
    //! \brief h_0 .. h_{L−1} of the last fit. \return L taps.
    const std::vector<gr_complex>& taps() const { return d_h; }
    //! \brief g_0 .. g_{L−1} (the image) of the last fit; zeros when not widely linear. \return L taps.
    const std::vector<gr_complex>& image_taps() const { return d_g; }
    //! \brief c, the DC of the last fit (0 without DC). \return c.
    gr_complex dc() const { return d_c; }
    //! \brief Windows processed. \return the count.
    unsigned long long windows() const { return d_windows; }
    //! \brief Forgets the fit and the transmitted history (a new stream).
    void reset();
    /*!
     * \brief Takes the windows fitted so far as a stream's steady state: as if every earlier
     *        window had been like them. Multiplies the accumulated normal equations by
     *        Σ_k λ^k = 1/(1 − λ), the weight the forgotten history has in a long stream, so the
     *        next window's own share of the fit is the steady state's (1 − λ) and not 1/(1 + λ).
     *        A model of one frame of a stream (front_end_frame.h) calls it after one window of
     *        the leakage alone.
     */
    void hold_as_steady_state();

private:
    leakage_canceller_settings d_set;
    std::vector<std::complex<double>> d_r, d_p; // K×K normal matrix (row-major), K right side
    std::vector<gr_complex> d_hist;              // tx: L − 1 history samples, then the window
    std::vector<gr_complex> d_h, d_g;
    gr_complex d_c{ 0.0f, 0.0f };
    unsigned long long d_windows = 0;

    std::vector<unsigned char> d_clipped;        // per window sample: bit 0 I, bit 1 Q at full scale

    void regressors(size_t n, std::complex<double>* phi) const; // φ at window sample n
    void mark_clipped(const gr_complex* rx);                    // fills d_clipped (clip_level > 0)
    void add_window_normal_matrix();                           // R += the window's Σ conj(φ)·φᵀ
    std::vector<std::complex<double>> d_prefix_direct, d_prefix_image; // its lagged prefix sums
    std::vector<std::complex<double>> d_fit;                           // the window's fitted leakage
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_LEAKAGE_CANCELLER_H */
