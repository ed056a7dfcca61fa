// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the radio file reader. Any input either loads or is refused with
 * std::invalid_argument; a radio that loads is valid and survives its own round trip. */
#include <gnuradio/sems/core/radio/front_end.h>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto s = gr::sems::front_end_settings::parse(text, "fuzz");
        s.validate();
        if (!(gr::sems::front_end_settings::parse(s.to_json_string(), "round trip") == s))
            std::abort();
        (void)s.leakage_response();
        (void)s.phase_diffusion();
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
