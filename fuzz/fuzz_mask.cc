// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the pilot mask reader. Any input either loads or is refused with
 * std::invalid_argument; anything else (another exception, a crash, a sanitizer report)
 * is a finding. A mask that loads must survive its own round trip. */
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto m = gr::sems::pilot_mask::parse(text, "fuzz");
        const auto back = gr::sems::pilot_mask::parse(m.to_json_string(), "round trip");
        if (!(back == m))
            std::abort();
        (void)m.dense();
        (void)m.carrier_lists();
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
