// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the pilot mask readers, one frame's (pilot_mask), a super-frame's
 * (super_frame_mask, which reads both forms) and a MIMO mask's (mimo_mask). Any input either
 * loads or is refused with std::invalid_argument; anything else (another exception, a crash, a
 * sanitizer report) is a finding. A mask that loads must survive its own round trip; a
 * one-frame file must read the same through both readers, and a super-frame's every set has
 * one count; a MIMO mask's every pilot has an element in range and one unit of energy. */
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    bool one_frame = false;
    gr::sems::pilot_mask one(1, 1, { { 0, 0 } });
    try {
        one = gr::sems::pilot_mask::parse(text, "fuzz");
        one_frame = true;
        const auto back = gr::sems::pilot_mask::parse(one.to_json_string(), "round trip");
        if (!(back == one))
            std::abort();
        (void)one.dense();
        (void)one.carrier_lists();
    } catch (const std::invalid_argument&) {
    }
    try {
        const auto sf = gr::sems::super_frame_mask::parse(text, "fuzz");
        const auto back = gr::sems::super_frame_mask::parse(sf.to_json_string(), "round trip");
        if (!(back == sf) || back.to_json() != sf.to_json())
            std::abort();
        for (const auto& set : sf.sets())
            if (set.size() != sf.pilots_per_frame() || set.n_symbols() != sf.n_symbols())
                std::abort();
        if (one_frame && (sf.n_frames() != 1 || !(sf.set(0) == one) || sf.to_json() != one.to_json()))
            std::abort(); // a one-frame file reads the same through both
    } catch (const std::invalid_argument&) {
        if (one_frame)
            std::abort(); // the super-frame reader takes every one-frame file
    }
    try {
        const auto m = gr::sems::mimo_mask::parse(text, "fuzz");
        if (!(gr::sems::mimo_mask::parse(m.to_json().dump(), "round trip") == m))
            std::abort();
        for (int k = 0; k < m.mask().size(); ++k) {
            double energy = 0.0;
            for (int j = 0; j < m.n_transmit(); ++j)
                energy += m.amplitude(k, j) * m.amplitude(k, j);
            if (std::fabs(energy - 1.0) > 1e-12)
                std::abort();
        }
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
