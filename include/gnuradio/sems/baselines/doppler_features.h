// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The classical micro-Doppler feature extractor (the feature-SVM baseline).
 *
 * \details Doppler spectrum from the pilots: for every subcarrier that carries pilots, the
 * slow-time periodogram of its pilots (a DFT over the symbols that carry them,
 * evaluated on the grid f_q = (q - F/2) / (F T), q = 0..F-1, F = N · oversample, i.e.
 * over [-1/(2T), 1/(2T))), summed over subcarriers:
 *     S(f) = Σ_m |Σ_{k: m_k = m} r_k exp(-j2π f n_k T)|².
 * Subcarriers with one pilot add only a flat floor; a lattice with few pilot symbols
 * aliases (that is what the Doppler-oriented pattern avoids).
 * With p(f) = S(f) / Σ S the features are the moments of the spectrum, as in
 * Kim & Moon (2009):
 *   0 mean        μ = Σ f p(f)                                   [Hz]
 *   1 std         σ = √Σ (f-μ)² p(f)                             [Hz]
 *   2 skewness    Σ ((f-μ)/σ)³ p(f)     (0 for a line: σ < 1e-3 of a grid step, 1/(oversample·N·T))
 *   3 kurtosis    Σ ((f-μ)/σ)⁴ p(f)     (0 for a line; not excess)
 * plus two classic descriptors:
 *   4 peak        argmax_f S(f), the bulk ("torso") Doppler       [Hz] — robust to
 *                 the spread that drags the mean
 *   5 entropy     -Σ p ln p / ln F, the normalised spectral entropy in [0, 1] — how
 *                 spread the micro-Doppler is, independent of where it sits.
 * An all-zero input gives all-zero features.
 */
#ifndef INCLUDED_SEMS_BASELINES_DOPPLER_FEATURES_H
#define INCLUDED_SEMS_BASELINES_DOPPLER_FEATURES_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <complex>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The classical micro-Doppler feature extractor (see the file's description). */
class SEMS_BASELINES_API doppler_features
{
public:
    static constexpr int n_features = 6; ///< features per frame
    /*! \brief The features' names. \return n_features names, in feature order. */
    static std::vector<std::string> names();

    /*!
     * \brief An extractor for a frame and a pilot pattern.
     * \param fs the frame. \param mask the pilot pattern.
     * \param oversample Doppler grid points per 1/(N·T), in [1, 64].
     * \throws std::invalid_argument naming the bad parameter.
     */
    doppler_features(const frame_settings& fs, const pilot_mask& mask, int oversample = 1);

    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const { return d_np; }
    /*! \brief The Doppler grid f_q. \return the frequencies in Hz. */
    const std::vector<double>& frequencies_hz() const { return d_freq; }
    /*!
     * \brief S(f) on the grid.
     * \param obs N_p observations in mask order.
     * \return the spectrum.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<double> spectrum(const gr_complex* obs) const;
    /*!
     * \brief The features of one frame.
     * \param obs N_p observations in mask order.
     * \return n_features values.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<double> extract(const gr_complex* obs) const;

private:
    int d_np;
    std::vector<double> d_freq;
    std::vector<int> d_group;               // per pilot: index of its subcarrier group
    int d_n_groups;
    std::vector<std::complex<double>> d_phasor; // F x N_p: exp(-j2π f_q n_k T)
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_DOPPLER_FEATURES_H */
