// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Pilot patterns for the MUSIC baselines (UP / RP / OP-MUSIC).
 *
 * \details UP-MUSIC uses pilot_mask::uniform. The two others are built here:
 *  - random_subcarrier_mask (RP): the uniform lattice's pilot symbols (as many as it
 *    has rows), each with its own seeded random set of subcarriers. Random lags fill
 *    the co-array irregularly: no grating lobes, but a short contiguous co-array.
 *  - nested_subcarrier_mask (OP): `rows` pilot symbols spread over the frame, each
 *    carrying a two-level nested array on the subcarriers, {0..N1-1} ∪ {(N1+1)k - 1,
 *    k = 1..N2}, with N1 + N2 = pilots per symbol and N1, N2 chosen to maximise the
 *    contiguous difference co-array (N1+1)·N2 within M. The optimised design for
 *    co-array MUSIC: with 16 pilots per symbol it gives lags 0..59 at spacing 1.
 *    Leftover pilots (count not a multiple of rows) go to one more spread symbol.
 */
#ifndef INCLUDED_SEMS_BASELINES_SUBCARRIER_MASKS_H
#define INCLUDED_SEMS_BASELINES_SUBCARRIER_MASKS_H

#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <cstdint>

namespace gr {
namespace sems {

/*!
 * \brief The RP-MUSIC pattern: the uniform lattice's pilot symbols, each with its own seeded
 *        random set of subcarriers.
 * \param n_symbols N. \param n_subcarriers M. \param count N_p. \param seed the seed.
 * \return the mask.
 * \throws std::invalid_argument on a bad count.
 */
SEMS_BASELINES_API pilot_mask random_subcarrier_mask(int n_symbols, int n_subcarriers, int count, uint64_t seed);
/*!
 * \brief The OP-MUSIC pattern: `rows` spread pilot symbols, each carrying a two-level nested
 *        array on the subcarriers.
 * \param n_symbols N. \param n_subcarriers M. \param count N_p. \param rows pilot symbols.
 * \return the mask.
 * \throws std::invalid_argument on a bad count or rows.
 */
SEMS_BASELINES_API pilot_mask nested_subcarrier_mask(int n_symbols, int n_subcarriers, int count, int rows = 2);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_SUBCARRIER_MASKS_H */
