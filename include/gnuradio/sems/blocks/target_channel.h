// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The frequency-domain target channel emulator block (docs/design.md §1, §3).
 */
#ifndef INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_H
#define INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The frequency-domain target channel emulator (docs/design.md §1, §3): y = H[n,:] ⊙ x + V per OFDM symbol.
 *
 * \details gr_complex[M] in and out, one OFDM symbol per item: y = H[n,:] ⊙ x + V.
 *
 * With an array in the scene (array_geometry.h), one input per transmit element and one output
 * per receive element, as GNU Radio's multi-channel sources give theirs: receive element k
 * gives y_k = Σ_j H_{k,j}[n,:] ⊙ x_j + V_k, H_{k,j} the channel of receive element k with
 * transmit element j (channel_model::factors with element k·N_t + j), V_k its own noise. Every
 * output carries the truth tag. n_receive and n_transmit must be the array's counts (1 and 1
 * without an array): a mismatch is refused, naming both. The array comes from the scene file
 * or JSON, or, for random scenes, from `array` with each target's azimuth drawn from
 * [azimuth_min_rad, azimuth_max_rad].
 * A thin adapter over channel_model: per frame draw(frame) and factors(r, frame·N),
 * per symbol apply_row and add_noise. Everything per frame happens at the frame
 * start; nothing is allocated per item.
 *
 * Frames: aligned to keys::frame_tag tags when present (the frame index is the tag's
 * value, a tag mid-frame starts a new frame), counted from 0 otherwise. Each frame
 * draws the next realization of the model, so the same seed gives the same frames as
 * channel_model::generate and, with any SNR, the same channels (noise has its own
 * generator). keys::truth_tag (a PMT dict: class, class_name, class_library, delay_s,
 * delay_index, range_m, velocity_mps, snr_db, n_paths, micro_motion, micro_motion_params,
 * frame, track_id, frame_in_track, and azimuth_rad, elevation_rad with an array; docs/design.md
 * §3) goes on the first symbol of every frame.
 *
 * The scene: `scene` is a scene file path or scene JSON text (starts with '{'),
 * or "" for random scenes drawn per frame (or per track of track_frames frames) from
 * `classes` (empty = every class) with the random options (n_targets, paths_per_target,
 * micro_doppler, heading, clutter_*, track_*, array, azimuth_min_rad, azimuth_max_rad).
 * The random options must keep their defaults with a fixed scene (a fixed scene
 * carries its own targets, clutter, array and directions), so nothing is silently ignored;
 * likewise an azimuth interval without an array is refused.
 *
 * SNR per resource element in dB against the unit mean channel power, +inf = noiseless;
 * settable while running, effective from the next frame (the truth tag says which).
 * Non-finite input symbols are passed through (the extractor skips their frame) and
 * counted.
 */
class SEMS_API target_channel : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<target_channel> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a target channel.
     * \param scene            scene file path, scene JSON text, or "" for random scenes
     * \param classes          random scenes: class names to draw from (empty = all)
     * \param n_targets        random scenes: targets per frame (the first is the target of interest)
     * \param paths_per_target random scenes: paths per target (1 = single path)
     * \param micro_doppler    random scenes: micro-Doppler for the classes that have it
     * \param heading          random scenes: "approaching" (radial velocity = +speed, the paper)
     *                         or "any" (speed·cos θ, θ uniform on [0, 2π)); see heading_kind
     * \param clutter_paths    random scenes: static clutter scatterers (0 = no clutter)
     * \param clutter_csr_db   random scenes: clutter-to-signal ratio when clutter_paths > 0
     * \param snr_db           SNR per resource element, +inf = noiseless; with a scene's link
     *                         budget, the noise floor's shift from the budget's thermal noise
     *                         (0 dB: the budget as stated; the truth's snr_db is then the target's)
     * \param seed             seed of the model's draws (scene/gains and noise)
     * \param n_symbols        N (frame_settings::n_symbols)
     * \param n_subcarriers    M, the vector length (frame_settings::n_subcarriers)
     * \param bandwidth_hz     B (frame_settings::bandwidth_hz)
     * \param carrier_hz       f_c (frame_settings::carrier_hz)
     * \param symbol_interval_s T (frame_settings::symbol_interval_s)
     * \param class_library    random scenes: the class library `classes` names classes of, by
     *                         name ("paper", "kinematic") or file (class_library::find); a fixed
     *                         scene names its own in its "classes" key
     * \param track_frames     random scenes: 0 draws every frame afresh (the paper); K > 0 follows
     *                         each target for K frames (random_spec::tracks): it moves, its phases
     *                         go on, and the truth tag's track_id and frame_in_track say where it is
     * \param track_gains      tracks: how the gains evolve, "frame" (independent per frame),
     *                         "track" (constant) or "gauss_markov" (gain_coherence)
     * \param track_coherence_time_s tracks with "gauss_markov" gains: the coherence time τ_c in s
     * \param n_receive        output streams: the scene's array's receive elements (1 without one)
     * \param n_transmit       input streams: the scene's array's transmit elements (1 without one)
     * \param track_motion     tracks: how the bodies move, "radial" (along the line of sight) or
     *                         "straight" (a straight line in the ground plane: range, azimuth and
     *                         radial velocity follow the body; track_motion)
     * \param array            random scenes: the receiving array, a preset's name ("ula8_3g"), an
     *                         array file or its JSON text (array_from_setting); "" = none (one
     *                         antenna); n_receive and n_transmit must then be its counts
     * \param azimuth_min_rad  random scenes with an array: each target's azimuth is drawn from
     *                         U[azimuth_min_rad, azimuth_max_rad] in [−π, π] (random_spec); 0 and 0
     *                         = boresight (nothing drawn); refused without an array
     * \param azimuth_max_rad  random scenes with an array: the azimuth interval's upper end
     *                         (>= azimuth_min_rad)
     * \return the block.
     * \throws std::invalid_argument naming the parameter (or scene file) and the problem.
     */
    static sptr make(const std::string& scene = "",
                     const std::vector<std::string>& classes = {},
                     int n_targets = 1,
                     int paths_per_target = 1,
                     bool micro_doppler = true,
                     const std::string& heading = "approaching",
                     int clutter_paths = 0,
                     double clutter_csr_db = 0.0,
                     double snr_db = std::numeric_limits<double>::infinity(),
                     uint64_t seed = 0,
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     double bandwidth_hz = frame_settings{}.bandwidth_hz,
                     double carrier_hz = frame_settings{}.carrier_hz,
                     double symbol_interval_s = frame_settings{}.symbol_interval_s,
                     const std::string& class_library = "paper",
                     int track_frames = 0,
                     const std::string& track_gains = "frame",
                     double track_coherence_time_s = track_draw_spec{}.coherence_time_s,
                     int n_receive = 1,
                     int n_transmit = 1,
                     const std::string& track_motion = "radial",
                     const std::string& array = "",
                     double azimuth_min_rad = 0.0,
                     double azimuth_max_rad = 0.0);

    /*!
     * \brief Sets the SNR from the next frame.
     * \param snr_db SNR per resource element in dB, +inf = noiseless.
     * \throws std::invalid_argument on NaN and -inf.
     */
    virtual void set_snr_db(double snr_db) = 0;
    /*! \brief The SNR. \return the SNR per resource element in dB. */
    virtual double snr_db() const = 0;

    /*! \brief The frame. \return the frame settings. */
    virtual const frame_settings& settings() const = 0;
    /*! \brief The scene. \return the scene as JSON text. */
    virtual std::string scene_json() const = 0;

    /*! \brief Frames started. \return the count. */
    virtual uint64_t frames() const = 0;
    /*! \brief Input symbols with a NaN/Inf element. \return the count. */
    virtual uint64_t nonfinite_symbols() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_H */
