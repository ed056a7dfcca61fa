// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Default settings of the sink blocks.
 */
#ifndef INCLUDED_SEMS_LEARNING_SINK_DEFAULTS_H
#define INCLUDED_SEMS_LEARNING_SINK_DEFAULTS_H

namespace gr {
namespace sems {

/*!
 * \brief Default settings of the sink blocks, which the three sinks, their bindings and the
 *        model cards' speed measurement (apps/model_card_speed.h) take from here (the GRC
 *        blocks repeat the values, checked by python/sems/qa/qa_grc_defaults.py).
 */
struct sink_defaults {
    static constexpr int batch_size = 32;      ///< frames per inference call
    static constexpr int threads = 1;          ///< LibTorch intra-op threads
    static constexpr int metrics_period = 100; ///< frames between `metrics` messages
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_SINK_DEFAULTS_H */
