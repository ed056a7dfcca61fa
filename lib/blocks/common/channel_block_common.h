// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the two target channel blocks (frequency and time domain) share
 * (internal): their scene parameters, their SNR check and their truth tag, so both
 * read the same parameters the same way and write the same sems_truth dict.
 */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_CHANNEL_BLOCK_COMMON_H
#define INCLUDED_SEMS_LIB_BLOCKS_CHANNEL_BLOCK_COMMON_H

#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <pmt/pmt.h>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

// Throws std::invalid_argument (prefixed by `who`) for NaN or -inf.
void check_snr(const char* who, double snr_db);

// A random scene's tracks as block parameters: frames = 0 draws every frame afresh.
struct track_options {
    int frames = 0;
    std::string gains = gain_coherence_name(track_draw_spec{}.gains);
    double coherence_time_s = track_draw_spec{}.coherence_time_s;
    std::string motion = track_motion_name(track_draw_spec{}.motion);
};

// A channel block's streams: outputs (receive elements) and inputs (transmit elements).
struct stream_counts {
    int receive = 1;
    int transmit = 1;
};

// A random scene's array as block parameters: `array` names it (array_from_setting: a preset's
// name, an array file or its JSON text; "" or blank: none, one antenna) and each target's
// azimuth is drawn from U[azimuth_min_rad, azimuth_max_rad] (random_spec; 0, 0: boresight,
// nothing drawn, so the frames of a block without them).
struct array_options {
    std::string array;
    double azimuth_min_rad = 0.0;
    double azimuth_max_rad = 0.0;
};

// The scene of a channel block's parameters: a scene file path or JSON text (starts with
// '{'), or "" for a random scene from the random options, which must then keep their
// defaults with a fixed scene. A random scene draws its classes (given by name) from
// `class_library` (a library name or file, class_library::find) and takes its array and
// azimuth interval from `arrays`; a fixed scene carries its own classes ("classes" key),
// array and directions. The scene's array (none: 1 x 1) must match `streams`. Throws
// std::invalid_argument prefixed by `who`, naming the parameter.
scene channel_block_scene(const char* who,
                          const std::string& text,
                          const std::vector<std::string>& classes,
                          int n_targets,
                          int paths_per_target,
                          bool micro_doppler,
                          const std::string& heading, // "approaching" | "any" (heading_kind)
                          int clutter_paths,
                          double clutter_csr_db,
                          const std::string& class_library,
                          const track_options& tracks = {},
                          const stream_counts& streams = {},
                          const array_options& arrays = {});

// The channel blocks' default class library (the paper's table).
constexpr const char* default_class_library = "paper";

// The sems_truth dict of a frame (keys from tags.h, interned once). Built per frame, so
// built cheaply: pmt::acons (the keys are distinct, so the same alist dict_add would
// build, without its search per key), class-name symbols interned once per class, and,
// PMTs being immutable, every entry but the frame's shared with the previous frame's dict
// while the truth and the SNR are unchanged (a fixed scene: one entry and one value
// allocated per frame instead of 27 allocations). One truth_dict per block (not shared
// between threads).
class truth_dict
{
public:
    // `library`: the scene's class library name (the `class_library` entry of every dict).
    explicit truth_dict(const std::string& library);
    const pmt::pmt_t& tag_key() const { return d_truth_key; }
    // The dict of a frame: `r`'s truth, and the drawn parameters of its target of
    // interest's body (r.truth_body) when it has one. `snr_setting_db`: the emulator's SNR
    // (with a link budget, added to the target's SNR from the radar equation).
    pmt::pmt_t make(const frame_realization& r, uint64_t frame, double snr_setting_db);

private:
    const pmt::pmt_t d_truth_key, d_frame, d_class, d_class_name, d_delay_s, d_delay_index, d_range_m,
        d_velocity_mps, d_snr_db, d_n_paths, d_micro_motion, d_micro_motion_params, d_class_library, d_track_id,
        d_frame_in_track, d_azimuth_rad, d_elevation_rad;
    pmt::pmt_t d_library_symbol; // the scene's library name, interned once
    std::vector<pmt::pmt_t> d_class_symbols; // by class id
    std::map<std::string, pmt::pmt_t> d_motion_symbols; // by micro-motion model name
    pmt::pmt_t d_tail;                       // the dict less its frame entry
    frame_truth d_tail_truth;
    std::optional<scatterer_body> d_tail_body; // the target of interest's body in the tail
    pmt::pmt_t d_no_params;                  // micro_motion_params without a body (PMT_NIL)
    double d_tail_snr_db = 0.0;
    bool d_tail_valid = false;
};

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_CHANNEL_BLOCK_COMMON_H */
