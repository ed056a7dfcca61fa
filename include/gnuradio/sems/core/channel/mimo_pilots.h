// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief What a MIMO mask's receiver observes of a drawn frame (core/array/mimo_mask.h),
 *        from the channel model's virtual streams.
 */
#ifndef INCLUDED_SEMS_CORE_MIMO_PILOTS_H
#define INCLUDED_SEMS_CORE_MIMO_PILOTS_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief A drawn frame's noiseless pilots as a MIMO mask's receiver observes them:
 *        y[k·N_p + i] = Σ_j amplitude(i, j) · H_{k·N_t+j}[n_i, m_i] (receive-element-major).
 * \param cm the channel model (its scene's array has the mask's N_t transmit elements).
 * \param r the frame. \param first_symbol the absolute slow-time index of row 0.
 * \param m the mask.
 * \return N_r·N_p values.
 * \throws std::invalid_argument naming both counts when the array's transmit elements are not the
 *         mask's, or both grids when the mask is not the model's frame.
 */
SEMS_API std::vector<gr_complex>
mimo_pilots(const channel_model& cm, const frame_realization& r, uint64_t first_symbol, const mimo_mask& m);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_MIMO_PILOTS_H */
