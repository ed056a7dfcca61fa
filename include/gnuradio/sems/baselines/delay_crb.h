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
 * σ² = 10^(-SNR/10) against unit mean channel power per resource element (DESIGN §1).
 *
 * Rayleigh fading (|α|² ~ Exp(1), fresh per frame): the frame-conditional bound has
 * an infinite mean (E[1/|α|²] diverges), but the MAE it implies for an efficient
 * (Gaussian) estimator, √(2/π)·std, averages to a finite √(2 · var₁) with var₁ the
 * bound at |α|² = 1, because E[1/|α|] = √π.
 */
#ifndef INCLUDED_SEMS_BASELINES_DELAY_CRB_H
#define INCLUDED_SEMS_BASELINES_DELAY_CRB_H

#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <gnuradio/sems/core/pilot_mask.h>

namespace gr {
namespace sems {

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
     * \brief MAE of an efficient estimator: √(2/π)·√var at fixed gain; with rayleigh = true
     *        averaged over |α|² ~ Exp(1): √(2·var at |α|² = 1).
     * \param fs the frame. \param mask the pilot pattern. \param snr_db SNR per resource element in dB.
     * \param doppler_known whether ν is known. \param rayleigh average over Rayleigh fading.
     * \return the MAE in delay indices.
     * \throws std::invalid_argument as variance_index().
     */
    static double mae_index(const frame_settings& fs,
                            const pilot_mask& mask,
                            double snr_db,
                            bool doppler_known = false,
                            bool rayleigh = true);
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
