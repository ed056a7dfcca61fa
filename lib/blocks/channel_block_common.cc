// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the two target channel blocks share (see channel_block_common.h). */
#include "blocks/channel_block_common.h"
#include <gnuradio/sems/core/tags.h>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

namespace gr {
namespace sems {
namespace detail {

void check_snr(const char* who, double snr_db)
{
    if (std::isnan(snr_db) || snr_db == -std::numeric_limits<double>::infinity())
        throw std::invalid_argument(std::string(who) + ": snr_db must be a number or +inf (noiseless), got " +
                                    std::to_string(snr_db));
}

scene channel_block_scene(const char* who,
                          const std::string& text,
                          const std::vector<std::string>& classes,
                          int n_targets,
                          int paths_per_target,
                          bool micro_doppler,
                          const std::string& heading,
                          int clutter_paths,
                          double clutter_csr_db)
{
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos) { // a fixed scene: file or JSON text
        const random_spec defaults;
        if (!classes.empty() || n_targets != defaults.n_targets ||
            paths_per_target != defaults.paths_per_target || micro_doppler != defaults.micro_doppler ||
            heading != heading_name(defaults.heading) || clutter_paths != 0 || clutter_csr_db != 0.0)
            throw std::invalid_argument(std::string(who) +
                                        ": classes, n_targets, paths_per_target, micro_doppler, heading and "
                                        "clutter_* "
                                        "describe random scenes; a fixed scene (scene = file or JSON) carries "
                                        "its own, so leave them at their defaults");
        if (text[first] == '{')
            return scene::parse(text, std::string(who) + " scene JSON");
        return scene::load(text);
    }

    random_spec r;
    if (!classes.empty()) {
        r.classes.clear();
        for (const auto& name : classes) {
            try {
                r.classes.push_back(class_from_name(name));
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument(std::string(who) + ": classes: " + e.what());
            }
        }
    }
    r.n_targets = n_targets;
    r.paths_per_target = paths_per_target;
    r.micro_doppler = micro_doppler;
    try {
        r.heading = heading_from_name(heading);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": heading: " + e.what());
    }
    std::optional<clutter_spec> clutter;
    if (clutter_paths < 0)
        throw std::invalid_argument(std::string(who) + ": clutter_paths must be >= 0, got " +
                                    std::to_string(clutter_paths));
    if (clutter_paths == 0 && clutter_csr_db != 0.0)
        throw std::invalid_argument(std::string(who) + ": clutter_csr_db = " + std::to_string(clutter_csr_db) +
                                    " has no effect with clutter_paths = 0: set clutter_paths > 0 to add "
                                    "clutter, or leave clutter_csr_db at 0");
    if (clutter_paths > 0) {
        clutter_spec c;
        c.n_paths = clutter_paths;
        c.csr_db = clutter_csr_db;
        clutter = c;
    }
    auto sc = scene::random(r, clutter);
    sc.validate(std::string(who) + " random scene");
    return sc;
}

truth_dict::truth_dict()
    : d_truth_key(pmt::intern(keys::truth_tag)),
      d_frame(pmt::intern(keys::frame)),
      d_class(pmt::intern(keys::class_id)),
      d_class_name(pmt::intern(keys::class_name)),
      d_delay_s(pmt::intern(keys::delay_s)),
      d_delay_index(pmt::intern(keys::delay_index)),
      d_range_m(pmt::intern(keys::range_m)),
      d_velocity_mps(pmt::intern(keys::velocity_mps)),
      d_snr_db(pmt::intern(keys::snr_db)),
      d_n_paths(pmt::intern(keys::n_paths))
{
}

namespace {
// Equal as stored (a -0 is not a +0): a cached PMT is reused only for the very same value.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
} // namespace

pmt::pmt_t truth_dict::make(const frame_truth& t, uint64_t frame, double snr_db)
{
    const bool same_tail = d_tail_valid && t.class_id == d_tail_truth.class_id &&
                           t.n_paths == d_tail_truth.n_paths && t.class_name == d_tail_truth.class_name &&
                           same_bits(t.delay_s, d_tail_truth.delay_s) &&
                           same_bits(t.delay_index, d_tail_truth.delay_index) &&
                           same_bits(t.range_m, d_tail_truth.range_m) &&
                           same_bits(t.velocity_mps, d_tail_truth.velocity_mps) && same_bits(snr_db, d_tail_snr_db);
    if (!same_tail) {
        if (t.class_id < 0)
            throw std::invalid_argument("sems_truth: negative class id " + std::to_string(t.class_id));
        const auto cls = static_cast<size_t>(t.class_id);
        if (cls >= d_class_symbols.size())
            d_class_symbols.resize(cls + 1);
        if (!d_class_symbols[cls]) // interning hashes and locks: once per class, not per frame
            d_class_symbols[cls] = pmt::string_to_symbol(t.class_name);
        pmt::pmt_t tail = pmt::make_dict();
        tail = pmt::acons(d_class, pmt::from_long(t.class_id), tail);
        tail = pmt::acons(d_class_name, d_class_symbols[cls], tail);
        tail = pmt::acons(d_delay_s, pmt::from_double(t.delay_s), tail);
        tail = pmt::acons(d_delay_index, pmt::from_double(t.delay_index), tail);
        tail = pmt::acons(d_range_m, pmt::from_double(t.range_m), tail);
        tail = pmt::acons(d_velocity_mps, pmt::from_double(t.velocity_mps), tail);
        tail = pmt::acons(d_snr_db, pmt::from_double(snr_db), tail);
        tail = pmt::acons(d_n_paths, pmt::from_long(t.n_paths), tail);
        d_tail = tail;
        d_tail_truth = t;
        d_tail_snr_db = snr_db;
        d_tail_valid = true;
    }
    return pmt::acons(d_frame, pmt::from_uint64(frame), d_tail);
}

} // namespace detail
} // namespace sems
} // namespace gr
