// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage_canceller implementation (see leakage_canceller.h). */
#ifndef INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H
#define INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H

#include <gnuradio/sems/blocks/leakage_canceller.h>
#include <atomic>
#include <mutex>
#include <string>
#include <vector>

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
    uint64_t held() const override { return d_held_count; }
    std::string stream_error() const override { return d_failed ? d_error : std::string(); }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    leakage_fit d_core;
    mutable std::mutex d_mutex; // the fit, read from other threads
    const uint64_t d_max_lead;
    // The transmitted samples taken but not yet paired: d_held[d_held_pos ..].
    std::vector<gr_complex> d_held;
    size_t d_held_pos = 0;
    std::atomic<uint64_t> d_held_count{ 0 };
    std::string d_error;               // written once, before d_failed is set
    std::atomic<bool> d_failed{ false };
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEAKAGE_CANCELLER_IMPL_H */
