// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: super-frame masks — F pilot sets of one count, and their file (an ordinary mask
 * file with a `frames` list in place of `pilots`; F = 1 is the ordinary file).
 *
 *   {"format": "sems.pilot_mask", "version": 1, "n_symbols": 32, "n_subcarriers": 64,
 *    "pilot_symbol": [1, 0], "n_frames": 2,
 *    "frames": [{"pilots": [[n, m], ...], "power": [...], "phases": ...}, {...}],
 *    "origin": {...}}
 */
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {
std::string set_name(const std::string& source, size_t f) { return source + " (frames[" + std::to_string(f) + "])"; }

void check_count(size_t n, const std::string& source)
{
    if (n < 1 || n > static_cast<size_t>(limits::max_super_frames))
        json_read::fail(source, "frames",
                        "a super-frame spans 1 to " + std::to_string(limits::max_super_frames) + " frames, got " +
                            std::to_string(n));
}
} // namespace

super_frame_mask::super_frame_mask(pilot_mask mask) : d_origin(mask.origin())
{
    d_sets.push_back(std::move(mask));
}

super_frame_mask::super_frame_mask(std::vector<pilot_mask> sets, nlohmann::json origin, const std::string& source)
    : d_sets(std::move(sets)), d_origin(std::move(origin))
{
    check_count(d_sets.size(), source);
    const auto& first = d_sets.front();
    for (size_t f = 1; f < d_sets.size(); ++f) {
        const auto& s = d_sets[f];
        const std::string which = "frames[" + std::to_string(f) + "]";
        if (s.n_symbols() != first.n_symbols() || s.n_subcarriers() != first.n_subcarriers())
            json_read::fail(source, which,
                            "is a " + std::to_string(s.n_symbols()) + " x " + std::to_string(s.n_subcarriers()) +
                                " grid but frames[0] is " + std::to_string(first.n_symbols()) + " x " +
                                std::to_string(first.n_subcarriers()));
        if (s.size() != first.size())
            json_read::fail(source, which,
                            "has " + std::to_string(s.size()) + " pilots but frames[0] has " +
                                std::to_string(first.size()) +
                                ": every frame of a super-frame carries the same count");
        if (s.pilot_symbol() != first.pilot_symbol()) {
            std::ostringstream both; // (re,im) as std::complex prints it
            both << "has the pilot symbol " << s.pilot_symbol() << " but frames[0] has " << first.pilot_symbol();
            json_read::fail(source, which, both.str());
        }
    }
}

super_frame_mask super_frame_mask::repeated(const pilot_mask& mask, int n_frames)
{
    check_count(n_frames < 1 ? 0 : static_cast<size_t>(n_frames), "repeated super-frame mask");
    return super_frame_mask(std::vector<pilot_mask>(static_cast<size_t>(n_frames), mask),
                            { { "kind", "repeated" }, { "mask", mask.origin() } }, "repeated super-frame mask");
}

super_frame_mask super_frame_mask::from_json(const nlohmann::json& j, const std::string& source)
{
    using namespace json_read;
    check_format(j, pilot_mask::format_name, pilot_mask::format_version, source);
    if (!j.contains("frames")) // an ordinary mask: F = 1
        return super_frame_mask(pilot_mask::from_json(j, source));
    object_reader r(j, source);
    for (const char* key : { "format", "version", "n_symbols", "n_subcarriers", "pilot_symbol" })
        r.allow(key);
    const auto& frames = r.require("frames");
    if (!frames.is_array())
        fail(source, "frames", "expected a list of one pilot set per frame, got " + object_reader::short_dump(frames));
    check_count(frames.size(), source);
    if (const auto* nf = r.find("n_frames")) {
        const auto declared = integer(*nf, "n_frames", source);
        if (declared != static_cast<long long>(frames.size()))
            fail(source, "n_frames",
                 "declares " + std::to_string(declared) + " frames but the list has " + std::to_string(frames.size()));
    }
    const auto* o = r.find("origin");
    nlohmann::json origin = o ? *o : nlohmann::json{ { "kind", "explicit" } };
    r.finish();
    std::vector<pilot_mask> sets;
    sets.reserve(frames.size());
    for (size_t f = 0; f < frames.size(); ++f) {
        const auto& set = frames[f];
        if (!set.is_object())
            fail(source, "frames[" + std::to_string(f) + "]",
                 "expected a JSON object with its \"pilots\", got " + object_reader::short_dump(set));
        // A set is an ordinary mask of the file's grid and symbol: read by the one mask reader.
        nlohmann::json one = set;
        for (const char* key : { "format", "version", "n_symbols", "n_subcarriers", "pilot_symbol" }) {
            if (set.contains(key))
                fail(source, "frames[" + std::to_string(f) + "]." + key, "belongs to the file, not to a frame's set");
            if (j.contains(key))
                one[key] = j[key];
        }
        sets.push_back(pilot_mask::from_json(one, set_name(source, f)));
    }
    return super_frame_mask(std::move(sets), origin, source);
}

super_frame_mask super_frame_mask::load(const std::string& path)
{
    return from_json(json_read::parse_file(path), path);
}

super_frame_mask super_frame_mask::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

nlohmann::json super_frame_mask::to_json() const
{
    if (d_sets.size() == 1) { // the ordinary file, bit for bit
        auto j = d_sets.front().to_json();
        j["origin"] = d_origin;
        return j;
    }
    auto j = d_sets.front().to_json();
    nlohmann::json frames = nlohmann::json::array();
    for (const auto& s : d_sets) {
        auto one = s.to_json();
        nlohmann::json set;
        for (const char* key : { "n_pilots", "pilots", "power", "phases" })
            if (one.contains(key))
                set[key] = one[key];
        frames.push_back(set);
    }
    for (const char* key : { "n_pilots", "pilots", "power", "phases" })
        j.erase(key);
    j["n_frames"] = n_frames();
    j["frames"] = frames;
    j["origin"] = d_origin;
    return j;
}

std::string super_frame_mask::to_json_string() const { return to_json().dump(); }

void super_frame_mask::save(const std::string& path) const { json_read::write_file(path, to_json()); }

void super_frame_mask::check_frame(const frame_settings& fs, const std::string& who) const
{
    for (size_t f = 0; f < d_sets.size(); ++f)
        d_sets[f].check_frame(fs, d_sets.size() == 1 ? who : who + " (super-frame set " + std::to_string(f) + ")");
}

void super_frame_mask::check_shape(int n_frames, int pilots_per_frame, const std::string& who,
                                   const std::string& expected) const
{
    if (n_frames != this->n_frames())
        throw std::invalid_argument(who + ": the mask spans a super-frame of F = " + std::to_string(this->n_frames()) +
                                    " frames but " + expected + " expects F = " + std::to_string(n_frames));
    if (pilots_per_frame != this->pilots_per_frame())
        throw std::invalid_argument(who + ": the mask has " + std::to_string(this->pilots_per_frame()) +
                                    " pilots per frame but " + expected + " expects " +
                                    std::to_string(pilots_per_frame));
}

} // namespace sems
} // namespace gr
