// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage_canceller implementation (see leakage_canceller.h). */
#include "blocks/leakage_canceller_impl.h"
#include <gnuradio/io_signature.h>

namespace gr {
namespace sems {

leakage_canceller::sptr
leakage_canceller::make(int taps, int window, double forgetting, bool widely_linear, bool dc)
{
    leakage_canceller_settings s;
    s.taps = taps;
    s.window = window;
    s.forgetting = forgetting;
    s.widely_linear = widely_linear;
    s.dc = dc;
    return gnuradio::make_block_sptr<leakage_canceller_impl>(s); // validated by the core
}

leakage_canceller_impl::leakage_canceller_impl(const leakage_canceller_settings& settings)
    : gr::sync_block("leakage_canceller",
                     gr::io_signature::make(2, 2, sizeof(gr_complex)),
                     gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_core(settings)
{
    set_output_multiple(settings.window); // whole windows: each is fitted and cancelled at once
    set_tag_propagation_policy(TPP_DONT); // rx's tags are copied in work(); tx's are dropped
}

std::vector<gr_complex> leakage_canceller_impl::taps() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.taps();
}

std::vector<gr_complex> leakage_canceller_impl::image_taps() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.image_taps();
}

gr_complex leakage_canceller_impl::dc() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.dc();
}

uint64_t leakage_canceller_impl::windows() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.windows();
}

int leakage_canceller_impl::work(int noutput_items,
                                 gr_vector_const_void_star& input_items,
                                 gr_vector_void_star& output_items)
{
    const auto* rx = static_cast<const gr_complex*>(input_items[0]);
    const auto* tx = static_cast<const gr_complex*>(input_items[1]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const int w = d_core.window();
    std::lock_guard<std::mutex> lock(d_mutex);
    const int n = noutput_items / w * w;
    for (int s = 0; s < n; s += w)
        d_core.process(rx + s, tx + s, out + s);
    std::vector<gr::tag_t> tags; // rx's tags, on the same samples
    get_tags_in_range(tags, 0, nitems_read(0), nitems_read(0) + uint64_t(n));
    for (const auto& t : tags)
        add_item_tag(0, t.offset, t.key, t.value, t.srcid);
    return n;
}

} // namespace sems
} // namespace gr
