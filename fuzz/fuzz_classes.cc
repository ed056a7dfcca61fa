// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the class-library reader and the random scenes drawn from a library.
 * Any input either loads or is refused with std::invalid_argument; a library that loads
 * survives its own round trip, and when it fits the paper's frame its random scene draws
 * frames that are finite, labelled with one of its classes, inside its intervals (seen by an
 * array, its angles too). */
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

using namespace gr::sems;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::shared_ptr<const class_library> lib;
    try {
        lib = class_library::from_json(nlohmann::json::parse(text), "fuzz");
    } catch (const std::invalid_argument&) {
        return 0;
    } catch (const nlohmann::json::exception&) {
        return 0; // not JSON at all: the file reader reports that (json_read::parse_text)
    }
    const auto j = lib->to_json();
    if (class_library::from_json(j, "round trip")->to_json() != j || !lib->same_classes(*lib))
        std::abort();
    for (auto heading : { heading_kind::approaching, heading_kind::any }) {
        random_spec r;
        r.classes.clear();
        r.heading = heading;
        const frame_settings fs;
        try {
            channel_model cm(fs, scene::random(r, std::nullopt, fading_kind::rayleigh, lib), size);
            std::vector<gr_complex> h(fs.grid_size());
            for (uint64_t f = 0; f < 2; ++f) {
                const auto fr = cm.draw(f * 1000003);
                if (fr.truth.class_id < 0 || fr.truth.class_id >= lib->size())
                    std::abort();
                const auto& c = lib->at(fr.truth.class_id);
                if (fr.truth.range_m < c.range_min_m || fr.truth.range_m > c.range_max_m ||
                    std::fabs(fr.truth.velocity_mps) > c.speed_max_mps)
                    std::abort();
                cm.factors(fr, f * 1000003 * fs.n_symbols).fill(h.data());
                for (auto x : h)
                    if (!std::isfinite(x.real()) || !std::isfinite(x.imag()))
                        std::abort();
            }
        } catch (const std::invalid_argument&) {
            // the library does not fit the paper's frame: refused, naming the class
        }
    }
    // Seen by a two-element array the truth carries the drawn angles: inside the class's own
    // intervals where it gives them.
    try {
        random_spec r;
        r.classes.clear();
        channel_model cm(frame_settings{},
                         scene::random(r, std::nullopt, fading_kind::none, lib).with_array(array_geometry::ula(2, 0.05)),
                         size);
        for (uint64_t f = 0; f < 2; ++f) {
            const auto t = cm.draw(f * 1000003).truth;
            const auto& c = lib->at(t.class_id);
            if (c.has_azimuth() && !(t.azimuth_rad >= c.azimuth_min_rad && t.azimuth_rad <= c.azimuth_max_rad))
                std::abort();
            if (c.has_elevation() && !(t.elevation_rad >= c.elevation_min_rad && t.elevation_rad <= c.elevation_max_rad))
                std::abort();
        }
    } catch (const std::invalid_argument&) {
        // as above
    }
    return 0;
}
