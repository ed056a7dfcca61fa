// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage_canceller implementation (see leakage_canceller.h). */
#ifndef INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H
#define INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H

#include <gnuradio/sems/blocks/leakage_canceller.h>
#include <mutex>

namespace gr {
namespace sems {

class leakage_canceller_impl : public leakage_canceller
{
public:
    explicit leakage_canceller_impl(const leakage_canceller_settings& settings);

    std::vector<gr_complex> taps() const override;
    std::vector<gr_complex> image_taps() const override;
    gr_complex dc() const override;
    uint64_t windows() const override;

    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    leakage_fit d_core;
    mutable std::mutex d_mutex;         // the fit, read from other threads
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H */
