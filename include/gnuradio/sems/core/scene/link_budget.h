// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A scene's optional link budget: the radar equation that sets each target's SNR from
 *        its range and RCS (docs/reference/link_budget.md).
 *
 * \details Without one, every target has unit mean power and the SNR is set per resource
 * element by the emulator (the paper). With one, a target at range R with mean RCS σ has the
 * SNR per resource element
 * \verbatim
   SNR = P_t G_t G_r λ² σ / ((4π)³ R⁴ k T_0 F B L)
   \endverbatim
 * (P_t the total transmit power spread over the M subcarriers, B = M Δf the frame's
 * bandwidth, λ = c/f_c the frame's wavelength, k Boltzmann's constant, T_0 the noise
 * temperature, F the noise figure, L the system loss): per subcarrier the signal is P_t/M and
 * the noise k T_0 F Δf, the same ratio. The emulator's SNR setting then shifts the noise
 * floor: 0 dB is the budget's thermal noise, +10 dB a floor 10 dB lower (a margin).
 */
#ifndef INCLUDED_SEMS_CORE_LINK_BUDGET_H
#define INCLUDED_SEMS_CORE_LINK_BUDGET_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <nlohmann/json.hpp>
#include <string>

namespace gr {
namespace sems {

/*! \brief A radar's link budget: powers and gains in dB units, the noise at T_0. */
struct SEMS_API link_budget {
    double tx_power_dbm = 20.0;         ///< P_t, the total transmit power, in dBm
    double tx_gain_dbi = 0.0;           ///< G_t, the transmit antenna's gain, in dBi
    double rx_gain_dbi = 0.0;           ///< G_r, the receive antenna's gain, in dBi
    double noise_figure_db = 6.0;       ///< F, the receiver's noise figure, in dB (≥ 0)
    double system_loss_db = 0.0;        ///< L, every other loss (cables, processing), in dB (≥ 0)
    double noise_temperature_k = 290.0; ///< T_0 in K (> 0)

    /// Nearest range the budget applies to: the radar equation's far field, and what keeps
    /// the R⁻⁴ law finite.
    static constexpr double min_range_m = 1.0;
    /// Boltzmann's constant in J/K (SI, exact since 2019).
    static constexpr double boltzmann_j_per_k = 1.380649e-23;

    /*!
     * \brief The SNR per resource element of a target.
     * \param fs the frame (its bandwidth and wavelength).
     * \param range_m the target's range, ≥ min_range_m.
     * \param rcs_dbsm its mean RCS in dBsm.
     * \return the SNR in dB at the budget's thermal noise.
     */
    double snr_db(const frame_settings& fs, double range_m, double rcs_dbsm) const;

    /*!
     * \brief Checks every field.
     * \param source names the file in errors. \param field the budget's path in it.
     * \throws std::invalid_argument naming `source`, the field and the problem.
     */
    void validate(const std::string& source, const std::string& field) const;
    /*! \brief The JSON object of the scene file. \return its keys, every one written. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads a budget; absent keys take their defaults.
     * \param j the object. \param source names the file in errors. \param field its path.
     * \return the budget, validated.
     * \throws std::invalid_argument naming `source` and the field.
     */
    static link_budget from_json(const nlohmann::json& j, const std::string& source, const std::string& field);
};

/*! \brief Equal budgets. \param a one. \param b another. \return true when every field is equal. */
SEMS_API bool operator==(const link_budget& a, const link_budget& b);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_LINK_BUDGET_H */
