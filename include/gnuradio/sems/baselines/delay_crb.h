// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The Cramér–Rao bound on the delay of a single path, for a pilot pattern.
 *
 * \details Model: r_k = α · exp(-j2π m_k Δf τ) · exp(j2π ν n_k T) + w_k, w_k ~ CN(0, σ²),
 * k over the N_p pilots; unknowns: τ, the complex gain α (|α| and its phase) and —
 * unless `doppler_known` — the Doppler ν. With φ the phase of α, ∂r_k/∂(τ, ν, φ) =
 * j r_k · g_k, g_k = (-2π Δf m_k, 2π T n_k, 1), and ∂r_k/∂|α| is orthogonal to those,
 * so the Fisher information of (τ, ν, φ) is (2|α|²/σ²) Σ_k g_k g_kᵀ. Inverting it:
 *
 *   var(τ̂) ≥ σ² / (2 |α|² (2π Δf)² S),
 *   S = S_mm                     (Doppler known)
 *   S = S_mm - S_mn² / S_nn      (Doppler unknown; S_nn = 0 → S_mm)
 *
 * with S_mm = Σ (m_k - m̄)², S_nn = Σ (n_k - n̄)², S_mn = Σ (m_k - m̄)(n_k - n̄).
 * In delay indices (τ·B = τ M Δf): var(idx) ≥ M² σ² / (2 |α|² (2π)² S).
 * σ² = 10^(-SNR/10) against unit mean channel power per resource element (docs/design.md §1).
 *
 * Rayleigh fading (|α|² ~ Exp(1), fresh per frame): the frame-conditional bound has
 * an infinite mean (E[1/|α|²] diverges), but the MAE it implies for an efficient
 * (Gaussian) estimator, √(2/π)·std, averages to a finite √(2 · var₁) with var₁ the
 * bound at |α|² = 1, because E[1/|α|] = √π. With mean path power p (|α|² ~ Exp(p)) it is
 * √(2 · var₁ / p): the single-path bound "drawn at" the direct path's mean power.
 *
 * Multipath (multipath_variance_index): r_k = b_k(ν) Σ_l α_l a_k(τ_l) + w_k, all L delays,
 * L complex gains and (unless `doppler_known`, and only if the pilots span two or more
 * symbols) the shared Doppler unknown. J has the columns ∂μ/∂τ_l = α_l (−j2π m_k / M) μ_kl,
 * ∂μ/∂ν = j2π n_k T μ_k, ∂μ/∂Re α_l = b_k a_k(τ_l), ∂μ/∂Im α_l = j b_k a_k(τ_l); the Fisher
 * information is (2/σ²) Re(JᴴJ) and the bound on the first path's delay is the (τ_1, τ_1)
 * element of its inverse. With one path it equals variance_index at gain_power = |α|².
 *
 * A mask whose pilots differ in energy (pilot_mask::power) observes pilot k with noise
 * σ²/p_k: each pilot's term of the Fisher information is weighted by p_k (in S: weighted
 * means and sums over the pilots; in the multipath bound: row k of J times sqrt(p_k)).
 */
#ifndef INCLUDED_SEMS_BASELINES_DELAY_CRB_H
#define INCLUDED_SEMS_BASELINES_DELAY_CRB_H

#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <complex>
#include <vector>

namespace gr {
namespace sems {

/*! \brief One path of a multipath bound: its delay (delay index) and complex gain. */
struct SEMS_BASELINES_API crb_path {
    double delay_index = 0.0;            ///< delay index τ·B
    std::complex<double> gain{ 1.0, 0.0 }; ///< complex gain α
};

/*! \brief The Cramér–Rao bound on the delay of a single path, for a pilot pattern (see the file's description). */
struct SEMS_BASELINES_API delay_crb {
    /*!
     * \brief Variance bound of the delay index for a path of power |α|² = gain_power.
     * \param fs the frame. \param mask the pilot pattern. \param snr_db SNR per resource element in dB.
     * \param doppler_known whether ν is known (else it is a nuisance parameter).
     * \param gain_power |α|².
     * \return the bound on var(τ̂·B).
     * \throws std::invalid_argument for NaN SNR, gain_power <= 0, or a pattern whose
     *         pilots all sit on one subcarrier (no delay information: S = 0).
     */
    static double variance_index(const frame_settings& fs,
                                 const pilot_mask& mask,
                                 double snr_db,
                                 bool doppler_known = false,
                                 double gain_power = 1.0);
    /*!
     * \brief MAE of an efficient estimator: √(2/π)·√var at fixed gain |α|² = mean_power; with
     *        rayleigh = true averaged over |α|² ~ Exp(mean_power).
     * \param fs the frame. \param mask the pilot pattern. \param snr_db SNR per resource element in dB.
     * \param doppler_known whether ν is known. \param rayleigh average over Rayleigh fading. \param mean_power the path's mean power |α|².
     * \return the MAE in delay indices.
     * \throws std::invalid_argument as variance_index().
     */
    static double mae_index(const frame_settings& fs,
                            const pilot_mask& mask,
                            double snr_db,
                            bool doppler_known = false,
                            bool rayleigh = true,
                            double mean_power = 1.0);
    /*!
     * \brief Variance bound of the FIRST path's delay index (paths[0]) in multipath (see above).
     * \param fs the frame; \param mask the pilots; \param snr_db noise σ² = 10^(−SNR/10);
     * \param paths the true paths, paths[0] the one bounded; \param doppler_known ν given.
     * \return the bound; +inf when the information is singular (coincident paths, or more
     *         unknowns than the pilots can resolve); 0 at SNR = +inf.
     * \throws std::invalid_argument for NaN SNR, no paths, a non-finite delay or gain, a zero
     *         first-path gain, or a mask that does not fit the frame.
     */
    static double multipath_variance_index(const frame_settings& fs,
                                           const pilot_mask& mask,
                                           double snr_db,
                                           const std::vector<crb_path>& paths,
                                           bool doppler_known = false);
    /*!
     * \brief The pattern's effective subcarrier spread S (see the file's description).
     * \param mask the pilot pattern. \param doppler_known whether ν is known.
     * \return S.
     */
    static double spread(const pilot_mask& mask, bool doppler_known);
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_DELAY_CRB_H */
