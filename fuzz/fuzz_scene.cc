// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the scene reader. Any input either loads or is refused with
 * std::invalid_argument; a scene that loads must survive its own round trip. */
#include <gnuradio/sems/core/scene/scene.h>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto s = gr::sems::scene::parse(text, "fuzz");
        const auto j = s.to_json();
        if (gr::sems::scene::parse(j.dump(), "round trip").to_json() != j)
            std::abort();
        (void)s.label_classes();
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
