// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the two target channel blocks share (see channel_block_common.h). */
#include "blocks/channel_block_common.h"
#include <gnuradio/sems/core/tags.h>
#include <cmath>
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
                          int clutter_paths,
                          double clutter_csr_db)
{
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos) { // a fixed scene: file or JSON text
        const random_spec defaults;
        if (!classes.empty() || n_targets != defaults.n_targets ||
            paths_per_target != defaults.paths_per_target || micro_doppler != defaults.micro_doppler ||
            clutter_paths != 0 || clutter_csr_db != 0.0)
            throw std::invalid_argument(std::string(who) +
                                        ": classes, n_targets, paths_per_target, micro_doppler and clutter_* "
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
    std::optional<clutter_spec> clutter;
    if (clutter_paths < 0)
        throw std::invalid_argument(std::string(who) + ": clutter_paths must be >= 0, got " +
                                    std::to_string(clutter_paths));
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

pmt::pmt_t truth_dict::make(const frame_truth& t, uint64_t frame, double snr_db) const
{
    pmt::pmt_t dict = pmt::make_dict();
    dict = pmt::dict_add(dict, d_frame, pmt::from_uint64(frame));
    dict = pmt::dict_add(dict, d_class, pmt::from_long(t.class_id));
    dict = pmt::dict_add(dict, d_class_name, pmt::string_to_symbol(t.class_name));
    dict = pmt::dict_add(dict, d_delay_s, pmt::from_double(t.delay_s));
    dict = pmt::dict_add(dict, d_delay_index, pmt::from_double(t.delay_index));
    dict = pmt::dict_add(dict, d_range_m, pmt::from_double(t.range_m));
    dict = pmt::dict_add(dict, d_velocity_mps, pmt::from_double(t.velocity_mps));
    dict = pmt::dict_add(dict, d_snr_db, pmt::from_double(snr_db));
    dict = pmt::dict_add(dict, d_n_paths, pmt::from_long(t.n_paths));
    return dict;
}

} // namespace detail
} // namespace sems
} // namespace gr
