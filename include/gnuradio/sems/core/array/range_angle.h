// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The range–angle map of one frame of an array's pilots: each element's delay profile
 *        per symbol, beamformed over the elements, its power averaged over the symbols, in dB.
 *
 * \details With element k's pilot grid X_k[n,m] (the pilot extractor's element-major output
 * placed on the N×M grid, zero off the pilots), its windowed delay profile per symbol
 *   D_k[n,q] = Σ_m w_m X_k[n,m] exp(+j2π m q/M) / Σw_m
 * and the steering vector s(φ) of the array (steering.h, the emulator's), the map is
 *   P[a,q] = (1/N) Σ_n |Σ_k conj(s_k(φ_a)) D_k[n,q]|² / (K · Σ_k |s_k(φ_a)|²)
 * in dB, row a = azimuth φ_a = −π/2 + π(a + ½)/A (A rows over the front half-plane, centres),
 * column q = delay index q. A unit point target at an integer delay index k and azimuth φ_a
 * on a full grid reads 0 dB at cell (a, k) with isotropic elements, whatever its Doppler (the
 * symbols are averaged in power); with cosine elements it reads its pattern's power there,
 * 20·log10 g(φ_a). Off-pilot cells are zero: a sparse mask lowers the peak to the mean over the symbols
 * of each symbol's windowed fill squared, (Σ_{pilot m} w_m / Σ_m w_m)².
 * An empty cell reads floor_db (−300 dB), never −inf.
 */
#ifndef INCLUDED_SEMS_CORE_RANGE_ANGLE_H
#define INCLUDED_SEMS_CORE_RANGE_ANGLE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <complex>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Computes range–angle maps for one mask and one array, reusing its FFT plan. */
class SEMS_API range_angle
{
public:
    static constexpr float floor_db = -300.0f; //!< the value of a cell with no power

    /*!
     * \param mask         the pilot positions (N, M and where the observations go in the grid)
     * \param array        the array whose streams the observations are (K = N_r receive elements;
     *                     one transmit element: an array with more is refused)
     * \param wavelength_m λ at the carrier
     * \param n_angles     A, the map's azimuth rows over [−π/2, π/2] (2 .. 4096)
     * \param window       "hann" or "rect", over the subcarriers
     * \throws std::invalid_argument naming the parameter and the problem.
     */
    range_angle(const pilot_mask& mask,
                const array_geometry& array,
                double wavelength_m,
                int n_angles = 64,
                const std::string& window = "hann");
    ~range_angle();
    range_angle(const range_angle&) = delete;
    range_angle& operator=(const range_angle&) = delete;

    /*! \brief Rows of a map. \return A, the azimuths. */
    int n_angles() const { return d_a; }
    /*! \brief Columns of a map. \return M, the delay indices. */
    int n_delay() const { return d_m; }
    /*! \brief Floats per map. \return A·M. */
    int map_size() const { return d_a * d_m; }
    /*! \brief Observations per frame. \return K·N_p. */
    int n_observations() const { return d_k * d_np; }
    /*! \brief The azimuth of a row. \param row a in [0, A). \return φ_a in rad. */
    double azimuth_rad(int row) const;

    /*!
     * \brief One frame's map.
     * \param observations K·N_p pilot observations, element-major, each element's in mask order
     * \param out_db       A·M floats, row-major [azimuth row][delay index]
     */
    void compute(const gr_complex* observations, float* out_db);

private:
    struct plans;
    const pilot_mask d_mask;
    const int d_n, d_m, d_np, d_k, d_a;
    std::vector<float> d_wm;
    float d_wsum;
    std::vector<std::complex<float>> d_steer;  // A x K, conj(s_k(φ_a)) / (‖s‖·sqrt(K))
    std::vector<gr_complex> d_profile;         // K x M: one symbol's delay profiles
    std::vector<float> d_power;                // A x M accumulator
    std::unique_ptr<plans> d_plans;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_RANGE_ANGLE_H */
