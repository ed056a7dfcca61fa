// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the bundle.json reader (model_bundle::load, torch-free: the
 * weights are read later by bundle_decoder). The input becomes bundle.json in a
 * scratch directory next to a fixed 32 x 64 mask.json with 4 pilots. Any input either
 * loads or is refused with std::invalid_argument; a loaded classifier's class names
 * always match its n_classes. */
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace {
std::string scratch()
{
    static std::string dir;
    if (dir.empty()) {
        char tmpl[] = "/tmp/sems_fuzz_bundle_XXXXXX";
        dir = ::mkdtemp(tmpl);
        std::ofstream(dir + "/mask.json")
            << R"({"format": "sems.pilot_mask", "version": 1, "n_symbols": 32, "n_subcarriers": 64,)"
            << R"( "pilots": [[0, 0], [8, 16], [16, 32], [24, 48]]})";
    }
    return dir;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string dir = scratch();
    {
        std::ofstream out(dir + "/bundle.json", std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const auto b = gr::sems::model_bundle::load(dir);
        if (b.task == gr::sems::task_kind::classify) {
            const auto s = gr::sems::nn::classifier_settings::from_json(
                b.decoder.value("settings", nlohmann::json::object()), "fuzz");
            if (s.n_classes != static_cast<int>(b.class_names.size()))
                std::abort();
        }
        (void)b.to_json().dump();
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
