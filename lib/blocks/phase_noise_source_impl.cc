// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: phase_noise_source implementation (see phase_noise_source.h). */
#include "blocks/phase_noise_source_impl.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/radio/front_end.h>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

phase_noise_source::sptr phase_noise_source::make(double sample_rate_hz, double dbc_hz, double offset_hz, uint64_t seed)
{
    const char* const who = phase_noise_source_impl::who;
    // The front end's rules for the oscillator (below 0 dBc/Hz, on the 1/f² skirt) in one place.
    front_end_settings fe;
    fe.phase_noise_dbc_hz = dbc_hz;
    fe.phase_noise_offset_hz = offset_hz;
    try {
        fe.validate();
        return gnuradio::make_block_sptr<phase_noise_source_impl>(fe.phase_diffusion(), sample_rate_hz, seed);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": " + e.what());
    }
}

phase_noise_source_impl::phase_noise_source_impl(double diffusion, double sample_rate_hz, uint64_t seed)
    : gr::sync_block(who, gr::io_signature::make(0, 0, 0), gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_process(diffusion, sample_rate_hz, seed)
{
}

int phase_noise_source_impl::work(int noutput_items, gr_vector_const_void_star&, gr_vector_void_star& output_items)
{
    d_process.generate(static_cast<gr_complex*>(output_items[0]), static_cast<size_t>(noutput_items));
    d_samples += static_cast<uint64_t>(noutput_items);
    return noutput_items;
}

} // namespace sems
} // namespace gr
