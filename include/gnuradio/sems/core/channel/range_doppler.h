// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The range-Doppler map of one frame: a windowed 2-D DFT of the (pilot) grid, in dB.
 *
 * \details With the grid model H[n,m] = α·exp(-j2π m k/M)·exp(j2π ν n T) (steering.h), the map is
 *   P[d,q] = |Σ_n Σ_m w_n w_m X[n,m] exp(+j2π m q/M) exp(-j2π n (d - N/2)/N)|² / (Σw_n·Σw_m)²
 * in dB (10·log10), row d = Doppler bin d - N/2 (Doppler (d - N/2)/(N·T), zero Doppler in the middle
 * row), column q = delay index q (delay q/B). A unit-amplitude target on a full grid at an integer
 * delay index k and Doppler bin b reads 0 dB at cell (b + N/2 mod N, k mod M). Off-pilot cells are
 * zero (a sparse mask raises the sidelobes and lowers the peak by the windowed fill squared,
 * (Σ_pilots w_n·w_m / (Σw_n·Σw_m))²: the fill fraction squared with the rect window).
 * An empty cell reads floor_db (-300 dB), never -inf.
 */
#ifndef INCLUDED_SEMS_CORE_RANGE_DOPPLER_H
#define INCLUDED_SEMS_CORE_RANGE_DOPPLER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Computes range-Doppler maps for one mask (N×M grid), reusing its FFT plans.
 */
class SEMS_API range_doppler
{
public:
    static constexpr float floor_db = -300.0f; //!< the value of a cell with no power

    /*!
     * \param mask   the pilot positions (N, M and where the observations go in the grid)
     * \param window "hann" or "rect", applied along both axes
     * \throws std::invalid_argument naming `window` if it is neither.
     */
    range_doppler(const pilot_mask& mask, const std::string& window = "hann");
    ~range_doppler();
    range_doppler(const range_doppler&) = delete;
    range_doppler& operator=(const range_doppler&) = delete;

    /*! \brief Rows of a map. \return N, the Doppler bins. */
    int n_doppler() const { return d_n; }
    /*! \brief Columns of a map. \return M, the delay indices. */
    int n_delay() const { return d_m; }
    /*! \brief Floats per map. \return N·M. */
    int map_size() const { return d_n * d_m; }

    /*!
     * \brief One frame's map.
     * \param observations the N_p pilot observations in mask order (the pilot extractor's output)
     * \param out_db       N·M floats, row-major [Doppler row][delay index]
     */
    void compute(const gr_complex* observations, float* out_db);

    /*!
     * \brief The row of Doppler bin `bin` (any integer; periodic in N): (bin + N/2) mod N.
     * \param bin       the Doppler bin
     * \param n_symbols N
     * \return the row, in [0, N).
     */
    static int doppler_row(int bin, int n_symbols);

private:
    struct plans;
    const pilot_mask d_mask;
    const int d_n, d_m;
    std::vector<float> d_wn, d_wm;
    std::vector<int> d_flat; // grid index n·M+m of each pilot
    float d_norm;            // 1 / (Σw_n·Σw_m)²
    std::vector<gr_complex> d_grid;
    std::unique_ptr<plans> d_plans;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_RANGE_DOPPLER_H */
