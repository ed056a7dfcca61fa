// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The delay search window and grid shared by the classical delay estimators
 *        (periodogram, OMP, MUSIC).
 *
 * \details Delays are searched on an oversampled grid of delay
 * indices τ·B: step 1/oversample, over [min_index, max_index). The subcarrier
 * steering exp(-j2π m Δf τ) is periodic in the delay index with period M, so a
 * negative min_index searches the wrapped end of the unambiguous window.
 */
#ifndef INCLUDED_SEMS_BASELINES_DELAY_SEARCH_H
#define INCLUDED_SEMS_BASELINES_DELAY_SEARCH_H

#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The delay search window and grid of the classical delay estimators. */
struct SEMS_BASELINES_API delay_search {
    int oversample = 8;      ///< grid points per delay index (per 1/B seconds)
    double min_index = 0.0;  ///< inclusive
    double max_index = -1.0; ///< exclusive; -1 means M (the whole unambiguous window); other negatives are refused

    /*!
     * \brief Checks the fields against a frame.
     * \param fs the frame. \param who names the caller in errors.
     * \throws std::invalid_argument naming `who` and the bad field.
     */
    void validate(const frame_settings& fs, const std::string& who) const;
    /*!
     * \brief The grid in delay indices: min_index + q / oversample, q = 0, 1, ...
     * \param fs the frame (M bounds the default window).
     * \return the grid.
     */
    std::vector<double> grid(const frame_settings& fs) const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_DELAY_SEARCH_H */
