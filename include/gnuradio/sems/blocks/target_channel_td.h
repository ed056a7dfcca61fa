// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the time-domain target channel emulator (docs/design.md §3, time domain).
 *
 * gr_complex samples in and out at the sample rate B: a CP-OFDM stream (ofdm_tx), symbols
 * of S = M + cp_len samples back to back from the stream's first sample. A thin adapter
 * over the same channel_model as target_channel (per frame draw(frame), so one seed gives
 * the same targets and gains) and td_channel (the per-sample synthesis; its header states
 * the time convention: symbol s at slow time s·T, its sample k at s·T + k/B, the delay
 * acting on the contiguous stream, so a delay past the prefix gives ISI, and Doppler and
 * micro-Doppler phases per sample, so ICI appears).
 *
 * Frames of N symbols: aligned to keys::frame_tag tags on a symbol's first sample (the
 * frame index is the tag's value; a tag that is not on a symbol boundary is counted in
 * misaligned_tags() and ignored), counted from 0 otherwise. Consecutive tags (frame f after
 * f − 1) spaced other than N·(M + cp_len) samples come from a transmitter with another
 * cyclic prefix, whether or not they are on a symbol boundary: the block then stops the
 * stream (work() returns WORK_DONE), logs an error (naming both prefix lengths when the
 * spacing fits one) and keeps it in stream_error(). keys::truth_tag (the same
 * dict as target_channel) goes on the first sample of every frame.
 *
 * Noise CN(0, σ²) on every sample, σ² = 10^(-SNR/10): with ofdm_tx/ofdm_rx's unitary
 * FFTs this is the same per-resource-element SNR as target_channel. Settable while
 * running, effective from the next frame.
 *
 * Work sizes: the block asks the scheduler for whole symbols (output multiple S); any
 * number of symbols per call gives the same output.
 *
 * Arrays: with an array in the scene, one input per transmit element and one output per
 * receive element, as target_channel: output k = Σ_j (element k·N_t + j's td_channel of input j)
 * + its own noise; every output carries the truth tag; n_receive and n_transmit must be the
 * array's counts (1 and 1 without an array). The array comes from the scene file or JSON, or,
 * for random scenes, from `array` with each target's azimuth drawn from [azimuth_min_rad,
 * azimuth_max_rad]; like the other random options (classes, n_targets, paths_per_target,
 * micro_doppler, clutter_*), they must keep their defaults with a fixed scene, which carries its
 * own array and directions.
 */
#ifndef INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_TD_H
#define INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_TD_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Sample-level target channel emulator: the scenes of target_channel on a
 *        CP-OFDM sample stream, with fractional delays, ISI and ICI.
 * \ingroup sems
 */
class SEMS_API target_channel_td : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<target_channel_td> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a sample-level target channel.
     * \param scene            scene file path, scene JSON text, or "" for random scenes
     * \param classes          random scenes: class names to draw from (empty = all)
     * \param n_targets        random scenes: targets per frame (the first is the target of interest)
     * \param paths_per_target random scenes: paths per target (1 = single path)
     * \param micro_doppler    random scenes: micro-Doppler for the classes that have it
     * \param clutter_paths    random scenes: static clutter scatterers (0 = no clutter)
     * \param clutter_csr_db   random scenes: clutter-to-signal ratio when clutter_paths > 0
     * \param snr_db           SNR per resource element, +inf = noiseless; with a scene's link
     *                         budget, the noise floor's shift from the budget's thermal noise
     *                         (0 dB: the budget as stated; the truth's snr_db is then the target's)
     * \param seed             seed of the model's draws (scene/gains and noise)
     * \param n_symbols        N, symbols per frame
     * \param n_subcarriers    M, subcarriers (FFT size)
     * \param bandwidth_hz     B, the sample rate
     * \param carrier_hz       f_c
     * \param symbol_interval_s T, slow-time spacing of the symbols (>= (M + cp_len)/B)
     * \param cp_len           cyclic prefix in samples (0 .. M)
     * \param class_library    random scenes: the class library `classes` names classes of, by
     *                         name ("paper", "kinematic") or file (class_library::find); a fixed
     *                         scene names its own in its "classes" key
     * \param n_receive        output streams: the scene's array's receive elements (1 without one)
     * \param n_transmit       input streams: the scene's array's transmit elements (1 without one)
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
                     int clutter_paths = 0,
                     double clutter_csr_db = 0.0,
                     double snr_db = std::numeric_limits<double>::infinity(),
                     uint64_t seed = 0,
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     double bandwidth_hz = frame_settings{}.bandwidth_hz,
                     double carrier_hz = frame_settings{}.carrier_hz,
                     double symbol_interval_s = frame_settings{}.symbol_interval_s,
                     int cp_len = frame_settings{}.cp_len,
                     const std::string& class_library = "paper",
                     int n_receive = 1,
                     int n_transmit = 1,
                     const std::string& array = "",
                     double azimuth_min_rad = 0.0,
                     double azimuth_max_rad = 0.0);

    /*!
     * \brief Sets the SNR from the next frame.
     * \param snr_db SNR per resource element in dB, +inf = noiseless.
     * \throws std::invalid_argument on NaN and -inf.
     */
    virtual void set_snr_db(double snr_db) = 0;
    //! \brief The SNR. \return the SNR per resource element in dB.
    virtual double snr_db() const = 0;

    //! \brief The frame. \return the frame settings.
    virtual const frame_settings& settings() const = 0;
    //! \brief The scene. \return the scene as JSON text.
    virtual std::string scene_json() const = 0;

    virtual uint64_t frames() const = 0;            //!< \return frames started
    virtual uint64_t nonfinite_symbols() const = 0; //!< \return input symbols with a NaN/Inf sample
    virtual uint64_t misaligned_tags() const = 0;   //!< \return frame tags off a symbol boundary (ignored)
    /*!
     * \brief Why the block stopped the stream, empty while it runs: frame tags spaced for
     *        another cyclic prefix (the message names the transmitter's and this block's when
     *        the spacing fits one).
     * \return the error message, or "".
     */
    virtual std::string stream_error() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_TARGET_CHANNEL_TD_H */
