// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief What the emulator models (docs/design.md §1): targets, their paths, clutter, and
 * the target of interest; fixed (given values) or random (drawn per frame from the
 * class table). A scene models only what it has: no micro-Doppler on a target without
 * it, no clutter paths without clutter.
 *
 * \details Power bookkeeping: the mean path powers of one realization sum to 1 (unit mean
 * channel power per resource element). Clutter takes csr/(1+csr) of it, the targets
 * the rest, split by target power and then by path power. With a link budget a target's
 * paths share its SNR from the radar equation instead, and clutter has csr times the
 * targets' sum.
 */
#ifndef INCLUDED_SEMS_CORE_SCENE_H
#define INCLUDED_SEMS_CORE_SCENE_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/link_budget.h>
#include <gnuradio/sems/core/scene/micro_motion.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <nlohmann/json.hpp>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief One path of a target (the first is the direct path). */
struct SEMS_API path_spec {
    double excess_range_m = 0.0; ///< beyond the target's range (0 = the direct path)
    double power = 1.0;          ///< relative to the target's other paths
};

/*! \brief One target of a fixed scene. */
struct SEMS_API target_spec {
    target_class cls = target_class::car; ///< its class: an id in the scene's class library
    double range_m = 50.0;                ///< range in m
    double velocity_mps = 15.0; ///< radial, positive = Doppler > 0
    /*! \brief Its speed along its motion; NaN: |velocity_mps| (moving along the line of sight). */
    double speed_mps = std::numeric_limits<double>::quiet_NaN();
    /*! \brief θ between its motion and the line towards the radar (velocity = speed·cos θ·cos(elevation_rad)); used with speed_mps. */
    double heading_rad = 0.0;
    std::optional<micro_doppler> md;      ///< its micro-Doppler (model `sinusoid`), if any
    std::optional<micro_motion> motion;   ///< its scatterer micro-motion (rotor, walker, wheels, scatterers), if any
    double power = 1.0;                        ///< relative to the scene's other targets (unused with a link budget)
    std::vector<path_spec> paths{ path_spec{} }; ///< at least one; the first is the direct path
    /*! \brief Its mean RCS in dBsm: with a link budget, its power follows the radar equation (NaN: none given). */
    double rcs_dbsm = std::numeric_limits<double>::quiet_NaN();
    /*! \brief Its line of sight's azimuth φ in [−π, π] (array_geometry.h's frame; 0: boresight). */
    double azimuth_rad = 0.0;
    /*!
     * \brief Its line of sight's elevation in [−π/2, π/2]: the body moves in the ground plane, so
     *        its radial velocity is speed·cos(heading)·cos(elevation); a walker below the array
     *        (elevation < 0) is seen from above. Non-zero only for point targets, sinusoids and
     *        walkers (the other scatterer models describe motion seen from the ground plane).
     */
    double elevation_rad = 0.0;
};

/*! \brief Static clutter: zero-Doppler scatterers at a clutter-to-signal power ratio. */
struct SEMS_API clutter_spec {
    double csr_db = 0.0;                ///< clutter-to-signal power ratio
    int n_paths = 4;                    ///< static (zero-Doppler) scatterers
    double range_min_m = 0.0;           ///< drawn per frame, unless ranges_m is given
    double range_max_m = 200.0;         ///< upper end of the drawn ranges
    std::vector<double> ranges_m;       ///< fixed scatterer ranges (then n_paths = ranges_m.size())
    /*!
     * \brief With ranges_m and an array: each fixed scatterer's azimuth in [−π, π] (empty: all 0).
     *        Drawn scatterers take an azimuth uniform on [−π/2, π/2) with their range.
     */
    std::vector<double> azimuths_rad;
};

/// Direction of a random target's motion. approaching: radial velocity = +speed (the
/// paper: every class in its own positive Doppler band). any: radial velocity =
/// speed·cos θ with θ ~ U[0, 2π) per frame (approaching, receding and crossing targets;
/// the bulk Doppler bands overlap, micro-Doppler must tell the classes apart).
enum class heading_kind { approaching, any };
/*! \brief The name of a heading. \param h the heading. \return "approaching" or "any". */
SEMS_API std::string heading_name(heading_kind h);
/*!
 * \brief The heading of a name.
 * \param name "approaching" or "any".
 * \return the heading.
 * \throws std::invalid_argument listing the known names.
 */
SEMS_API heading_kind heading_from_name(const std::string& name);

/*!
 * \brief A target's speed and heading.
 * \param t the target.
 * \return {speed, θ}: speed_mps and heading_rad when speed_mps is set, else |velocity| and 0 (approaching) or π.
 */
SEMS_API std::pair<double, double> target_speed_heading(const target_spec& t);

/// What a moving target does at the bounds of its track: start the pass again from its first
/// range, or turn around (its radial velocity changes sign).
enum class track_bound { restart, reflect };

/*!
 * \brief A fixed scene whose targets move: each range follows its radial velocity from frame
 *        to frame, R(t) = R_0 − v·t at the frame's first symbol (t = frame·N·T; no migration
 *        within a frame), inside [range_min_m, range_max_m].
 */
struct SEMS_API track_spec {
    double range_min_m = 0.0;   ///< the track's near end
    double range_max_m = 200.0; ///< the track's far end
    track_bound at_bound = track_bound::restart; ///< what a target does at an end
};

/// How a tracked target's complex gains evolve from frame to frame.
enum class gain_coherence {
    frame,       ///< drawn afresh every frame (the per-frame scenes' gains; Swerling II-like)
    track,       ///< drawn once and kept over the track (Swerling I-like)
    gauss_markov ///< α_f = ρ·α_{f−1} + √(1−ρ²)·w_f, ρ = exp(−N·T/τ_c), w_f ~ CN(0, p): first-order Gauss–Markov
};
/*! \brief The name of a coherence. \param c the coherence. \return "frame", "track" or "gauss_markov". */
SEMS_API std::string gain_coherence_name(gain_coherence c);
/*!
 * \brief The coherence of a name.
 * \param name "frame", "track" or "gauss_markov".
 * \return the coherence.
 * \throws std::invalid_argument listing the known names.
 */
SEMS_API gain_coherence gain_coherence_from_name(const std::string& name);

/// How a track's bodies move from frame to frame (track_draw_spec::motion).
enum class track_motion {
    radial,  ///< along the line of sight: R_f = R_0 − v·f·N·T; azimuth, elevation, heading and radial velocity kept
    straight ///< along a straight line in the ground plane at the body's speed and heading: range, azimuth, elevation, heading to the line of sight and radial velocity follow its position
};
/*! \brief The name of a track motion. \param m the motion. \return "radial" or "straight". */
SEMS_API std::string track_motion_name(track_motion m);
/*!
 * \brief The track motion of a name.
 * \param name "radial" or "straight".
 * \return the motion.
 * \throws std::invalid_argument listing the known names.
 */
SEMS_API track_motion track_motion_from_name(const std::string& name);

/*!
 * \brief How a random scene follows its targets across frames (docs/design.md §1, tracks).
 *
 * \details A track draws its targets once (class, parameters, range, speed, heading, extra
 * paths, clutter ranges) and keeps them for K frames, K ~ U{frames_min, ..., frames_max}. The
 * bodies move, evaluated at each frame's first symbol (no migration within a frame):
 * - track_motion::radial (the default): range follows the radial velocity, R_f = R_0 − v·f·N·T,
 *   at a constant radial velocity, heading and direction;
 * - track_motion::straight: the body moves d = s·f·N·T (s its speed) along a straight line in
 *   the ground plane, its height kept; with ρ_0 = R_0 cos ε_0 and z = R_0 sin ε_0, its horizontal
 *   position is (ρ_0 − d cos θ_0, d sin θ_0) along and across the first line of sight, so
 *   ρ_f = hypot(ρ_0 − d cos θ_0, d sin θ_0), R_f = hypot(ρ_f, z), ε_f = atan2(z, ρ_f), the
 *   azimuth and the heading both turn by δ_f = atan2(d sin θ_0, ρ_0 − d cos θ_0) (a heading
 *   θ in (0, π) moves towards increasing azimuth), and the radial velocity is s·cos θ_f·cos ε_f.
 *   The carrier phase stays continuous across frames: a target's paths turn by
 *   4π(R_0 − R_f)/λ − 2π f_D,f·t_f, the range travelled less what the frame's Doppler phasor
 *   (at t_f = f·N·T) already accounts for.
 * Slow time is the track's own clock, t = (f·N + n)·T from its first frame, so micro-motion and
 * Doppler phases continue across its frames and the same (seed, track index) gives the same
 * frames in a stream and in training. A track ends early at its last frame whose ranges all lie
 * inside their classes' range intervals (a body never leaves them) and, moving straight, whose
 * azimuths lie inside the intervals they were drawn from (the class's or the scene's; a single
 * value bounds nothing); the next frame starts the next track.
 */
struct SEMS_API track_draw_spec {
    int frames_min = 64; ///< shortest planned track, in frames (≥ 1)
    int frames_max = 64; ///< longest planned track, in frames (≤ limits::max_track_frames)
    gain_coherence gains = gain_coherence::frame; ///< how the gains evolve over a track
    double coherence_time_s = 0.1;                ///< τ_c for gauss_markov (> 0); unused otherwise
    track_motion motion = track_motion::radial;   ///< how the bodies move (radial: the frames of scenes that do not name one)
};

/// How a random scene draws a frame.
struct SEMS_API random_spec {
    /*! \brief Class ids (in the scene's class library) the target of interest is drawn from; empty: every class. */
    std::vector<target_class> classes{ target_class::pedestrian, target_class::car, target_class::drone };
    int n_targets = 1;                 ///< the target of interest is target 0
    int paths_per_target = 1;          ///< 1 = single path
    double excess_range_min_m = 2.0;   ///< extra paths: excess range ~ U[min, max]
    double excess_range_max_m = 30.0;  ///< upper end of the extra paths' excess range
    double path_power_decay_db = 3.0;  ///< path k has mean power 10^(-k·decay/10) relative to path 0
    bool micro_doppler = true;         ///< false: the micro-Doppler-free experiment
    heading_kind heading = heading_kind::approaching; ///< see heading_kind
    /*! \brief Tracks: targets kept over several frames; empty: drawn afresh every frame (the paper). */
    std::optional<track_draw_spec> tracks;
    /*!
     * \brief Each target's azimuth ~ U[min, max] in [−π, π]; drawn (last, after its paths) only
     *        when min < max, so scenes without an interval keep their exact frames. A radial track
     *        keeps its azimuth; a straight one turns it with the body (track_draw_spec).
     */
    double azimuth_min_rad = 0.0;
    double azimuth_max_rad = 0.0; ///< see azimuth_min_rad
    /*!
     * \brief Each target's elevation ~ U[min, max] in [−π/2, π/2]; drawn after its azimuth, only
     *        when min < max (a single value is every target's). Its radial velocity becomes
     *        speed·cos(heading)·cos(elevation). Only classes seen from any elevation take one other
     *        than 0: point, sinusoid and walker classes (scene::validate refuses the others by name). A radial
     *        track keeps its elevation; a straight one moves it with the body (track_draw_spec).
     */
    double elevation_min_rad = 0.0;
    double elevation_max_rad = 0.0; ///< see elevation_min_rad
};

/*! \brief The gains' fading: Rayleigh (α_l ~ CN(0, p_l)) or none (|α_l|² = p_l). */
enum class fading_kind { rayleigh, none };

/*! \brief A scene: fixed targets, or random ones drawn per frame, with optional clutter. */
class SEMS_API scene
{
public:
    static constexpr const char* format_name = "sems.scene"; ///< the file's `format`
    static constexpr int format_version = 1;                 ///< the file's `version`

    /*!
     * \brief A fixed scene: given targets, optional clutter.
     * \param targets the targets (at least one).
     * \param clutter the clutter, if any.
     * \param target_of_interest index of the target the truth describes.
     * \param fading the gains' fading.
     * \param library the class library the targets' classes index (null: the paper's).
     * \return the scene.
     * \throws std::invalid_argument naming the bad field.
     */
    static scene fixed(std::vector<target_spec> targets,
                       std::optional<clutter_spec> clutter = std::nullopt,
                       int target_of_interest = 0,
                       fading_kind fading = fading_kind::rayleigh,
                       std::shared_ptr<const class_library> library = nullptr);
    /*!
     * \brief A random scene drawn per frame from the class table.
     * \param spec how frames are drawn.
     * \param clutter the clutter, if any.
     * \param fading the gains' fading.
     * \param library the class library spec.classes index (null: the paper's).
     * \return the scene.
     * \throws std::invalid_argument naming the bad field.
     */
    static scene random(random_spec spec,
                        std::optional<clutter_spec> clutter = std::nullopt,
                        fading_kind fading = fading_kind::rayleigh,
                        std::shared_ptr<const class_library> library = nullptr);

    /*!
     * \brief Reads a scene file (docs/reference/file_formats.md).
     * \param path the file.
     * \return the scene.
     * \throws std::invalid_argument naming the file and the field.
     */
    static scene load(const std::string& path);
    /*!
     * \brief Parses scene JSON text.
     * \param json_text the JSON. \param source names the text in errors.
     * \return the scene.
     * \throws std::invalid_argument naming `source` and the field.
     */
    static scene parse(const std::string& json_text, const std::string& source = "scene text");
    /*!
     * \brief Reads a scene from JSON.
     * \param j the JSON object. \param source names the origin in errors.
     * \return the scene.
     * \throws std::invalid_argument naming `source` and the field.
     */
    static scene from_json(const nlohmann::json& j, const std::string& source);
    /*! \brief The file format's JSON. \return the JSON object. */
    nlohmann::json to_json() const;
    /*! \brief The file format's JSON text. \return the text. */
    std::string to_json_string() const;
    /*! \brief Writes the scene file. \param path the file. \throws std::invalid_argument naming the file if it cannot be written. */
    void save(const std::string& path) const;

    /*! \brief Random or fixed. \return true for a random scene. */
    bool is_random() const { return d_random.has_value(); }
    /*! \brief The targets of a fixed scene. \return the targets (empty for a random scene). */
    const std::vector<target_spec>& targets() const { return d_targets; }
    /*! \brief How a random scene draws. \return the settings (empty for a fixed scene). */
    const std::optional<random_spec>& random_settings() const { return d_random; }
    /*! \brief The clutter. \return the clutter, if any. */
    const std::optional<clutter_spec>& clutter() const { return d_clutter; }
    /*! \brief The target of interest. \return its index in targets(). */
    int target_of_interest() const { return d_toi; }
    /*! \brief The gains' fading. \return the fading kind. */
    fading_kind fading() const { return d_fading; }
    /*! \brief Classes a frame of this scene can be labelled with (the target of interest's possible classes). \return the classes. */
    std::vector<target_class> label_classes() const;
    /*! \brief The class library the scene's classes come from. \return the library (`paper` unless set). */
    const class_library& library() const { return *d_library; }
    /*! \brief The class library, shared. \return the library. */
    std::shared_ptr<const class_library> library_ptr() const { return d_library; }
    /*!
     * \brief The same scene with its classes from another library (a random scene without a
     *        class list then draws every class of it).
     * \param lib the library. \return the scene.
     * \throws std::invalid_argument when a class id is beyond the library.
     */
    scene with_library(std::shared_ptr<const class_library> lib) const;
    /*! \brief Whether a fixed scene's targets move. \return its track, if any. */
    const std::optional<track_spec>& track() const { return d_track; }
    /*!
     * \brief The same fixed scene with moving targets.
     * \param t the track. \return the scene.
     * \throws std::invalid_argument for a random scene or a bad track.
     */
    scene with_track(track_spec t) const;
    /*!
     * \brief The link budget, if any: then each target's SNR per resource element follows the
     *        radar equation at its range and RCS, frame by frame (link_budget.h).
     * \return the budget (empty: unit mean power per target, the paper's).
     */
    const std::optional<link_budget>& budget() const { return d_budget; }
    /*!
     * \brief The same scene with a link budget.
     * \param b the budget.
     * \return the scene.
     * \throws std::invalid_argument when a target or class has no RCS or may come nearer than
     *         link_budget::min_range_m, naming it.
     */
    scene with_budget(link_budget b) const;
    /*!
     * \brief The receiving array, if the scene names one (array_geometry.h): then the emulator
     *        gives one stream per receive element and draws each clutter scatterer's azimuth.
     * \return the array (empty: one antenna, the paper's).
     */
    const std::optional<array_geometry>& array() const { return d_array; }
    /*! \brief The same scene received by an array. \param a the array. \return the scene. */
    scene with_array(array_geometry a) const;
    /*! \brief A class name in the scene's library. \param c the class id. \return its name. */
    std::string class_name(target_class c) const { return d_library->at(static_cast<int>(c)).name; }

    /*!
     * \brief Checks every field.
     * \param source names the scene in errors.
     * \throws std::invalid_argument naming `source` and the field.
     */
    void validate(const std::string& source = "scene") const;

private:
    scene() = default;
    void validate_budget(const std::string& source) const;
    std::vector<target_spec> d_targets;
    std::optional<random_spec> d_random;
    std::optional<clutter_spec> d_clutter;
    std::optional<track_spec> d_track;
    std::optional<link_budget> d_budget;
    std::optional<array_geometry> d_array;
    std::shared_ptr<const class_library> d_library = class_library::paper();
    int d_toi = 0;
    fading_kind d_fading = fading_kind::rayleigh;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_SCENE_H */
