// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: phase_noise_source implementation (see phase_noise_source.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_PHASE_NOISE_SOURCE_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_PHASE_NOISE_SOURCE_IMPL_H

#include <gnuradio/sems/blocks/phase_noise_source.h>
#include <gnuradio/sems/core/radio/phase_noise.h>
#include <atomic>

namespace gr {
namespace sems {

class phase_noise_source_impl : public phase_noise_source
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "phase_noise_source";

    phase_noise_source_impl(double diffusion, double sample_rate_hz, uint64_t seed);

    double diffusion() const override { return d_process.diffusion(); }
    uint64_t samples() const override { return d_samples; }

    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    phase_noise_process d_process;
    std::atomic<uint64_t> d_samples{ 0 };
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_PHASE_NOISE_SOURCE_IMPL_H */
