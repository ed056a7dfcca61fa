// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the array reader and each element's channel. Any input either loads or is
 * refused with std::invalid_argument; an array that loads survives its own round trip, and a
 * point target seen by it (fixed gain, from a direction the input's length picks) gives every
 * element a finite channel of the magnitude its pattern gives that direction. */
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
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
    array_geometry a;
    try {
        a = array_geometry::from_json(nlohmann::json::parse(text), "fuzz");
    } catch (const std::invalid_argument&) {
        return 0;
    } catch (const nlohmann::json::exception&) {
        return 0; // not JSON at all: the file reader reports that (json_read::parse_text)
    }
    if (!(array_geometry::from_json(a.to_json(), "round trip") == a))
        std::abort();
    if (size_t(a.n_receive()) * size_t(a.n_transmit()) > 64)
        return 0; // the channel below is per stream: keep an input's run short
    frame_settings fs;
    fs.n_symbols = 4;
    fs.n_subcarriers = 16;
    target_spec t;
    t.cls = target_class::car;
    t.range_m = 40.0;
    t.velocity_mps = 10.0;
    t.azimuth_rad = -M_PI + 2.0 * M_PI * double(size % 97) / 96.0;
    t.elevation_rad = -M_PI / 2 + M_PI * double(size % 31) / 30.0;
    try {
        channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a), 1);
        const auto r = cm.draw(0);
        const double want = element_pattern_amplitude(a.pattern(), direction_vector(t.azimuth_rad, t.elevation_rad));
        std::vector<gr_complex> h(size_t(fs.grid_size()));
        for (int k = 0; k < cm.n_elements(); ++k) {
            cm.factors(r, 0, k).fill(h.data());
            for (auto x : h)
                if (!std::isfinite(x.real()) || !std::isfinite(x.imag()) || std::fabs(std::abs(x) - want) > 1e-5)
                    std::abort();
        }
    } catch (const std::invalid_argument&) {
        // a range or Doppler the small frame refuses: not the array's business
    }
    return 0;
}
