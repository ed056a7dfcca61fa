// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief THE channel model (docs/design.md §1).
 *
 * \details The emulator block, the training app, the
 * evaluation and the Python bindings all draw their channels here.
 *
 * \verbatim
   H[n,m] = Σ_l α_l · exp(-j2π m Δf τ_l) · exp(j2π ν_l t_n) · exp(j (4π/λ) A_l sin(ω_l t_n + φ_l))
   Y[n,m] = H[n,m] · X[n,m] + V[n,m],   V ~ CN(0, σ²),  σ² = 10^(-SNR/10)
   \endverbatim
 *
 * H is separable per path: a delay factor over m times a slow-time factor over n,
 * so a frame costs L·(N + M) phase evaluations plus the N·M accumulation, and the
 * micro-Doppler factor is only evaluated for paths that have one.
 * t_n is absolute slow time (symbol index since the stream began, times T): phases
 * are reduced modulo one cycle in double precision, so a fixed scene keeps a
 * continuous, drift-free Doppler phase however long it streams.
 *
 * Draws are seeded and reproducible. Scene/gain draws and noise draws use separate
 * generators, so the same seed gives the same frames at every SNR.
 */
#ifndef INCLUDED_SEMS_CORE_CHANNEL_MODEL_H
#define INCLUDED_SEMS_CORE_CHANNEL_MODEL_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <complex>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

namespace detail {
struct expansion_plan; // lib/core/channel/scatterer_moments.h
}

/*! \brief One propagation path of one frame, with its gain already drawn. */
struct SEMS_API channel_path {
    /*! \brief τ_l, the round-trip delay in s. */
    double delay_s = 0.0;
    double doppler_hz = 0.0;      ///< ν_l in Hz
    double md_rate_hz = 0.0;      ///< 0: no micro-Doppler factor
    double md_amplitude_m = 0.0;  ///< A_l in m
    double md_phase_rad = 0.0;    ///< φ_l in rad
    std::complex<double> gain{ 1.0, 0.0 }; ///< α_l
    double mean_power = 1.0;               ///< p_l, the mean of |α_l|²
    int body = -1; ///< index of the target's scatterer body in frame_realization::bodies (-1: a point target)
    double azimuth_rad = 0.0;   ///< its direction from the array (array_geometry.h): φ
    double elevation_rad = 0.0; ///< θ
};

/*!
 * \brief Where the stream of one array element receives: the receive element's position plus
 *        the transmit element's (steering.h), and the elements' pattern. The default, the
 *        origin with an isotropic pattern, is the single-antenna model.
 */
struct SEMS_API array_element {
    position3 offset{ 0.0, 0.0, 0.0 }; ///< p_k + q_j in m
    element_pattern pattern = element_pattern::isotropic; ///< the elements' pattern
    /*! \brief Whether the element changes nothing (the origin, isotropic). \return true then. */
    bool is_origin() const
    {
        return offset[0] == 0.0 && offset[1] == 0.0 && offset[2] == 0.0 && pattern == element_pattern::isotropic;
    }
};

/*!
 * \brief A target made of moving scatterers (micro_motion.h) in one frame: its model with
 *        the parameters drawn for the frame, and the motion its scatterers move with.
 */
struct SEMS_API scatterer_body {
    micro_motion motion;      ///< the model and its parameters
    double speed_mps = 0.0;   ///< the target's speed (the walker's gait and the wheels' spin follow it)
    double heading_rad = 0.0; ///< θ between its motion and the line towards the radar (0: approaching head-on)
    /*!
     * \brief The radar's elevation seen from the body: minus its line of sight's elevation (a
     *        walker below the array is seen from above; the other models take 0).
     */
    double elevation_rad = 0.0;
};

/*! \brief Ground truth of one frame: the target of interest (its direct path). */
struct SEMS_API frame_truth {
    uint64_t frame = 0;      ///< frame index
    int class_id = 0;        ///< class id of the target of interest
    std::string class_name;  ///< its class name
    double delay_s = 0.0;    ///< round-trip delay in s
    double delay_index = 0.0; ///< τ·B
    double range_m = 0.0;      ///< range in m
    double velocity_mps = 0.0; ///< radial velocity in m/s
    double snr_db = 0.0;      ///< +inf when noiseless
    /*!
     * \brief With a link budget: the target of interest's SNR per resource element from the
     *        radar equation at this frame's range, at the budget's thermal noise (the emulator's
     *        SNR setting adds to it). NaN without a link budget.
     */
    double link_snr_db = std::numeric_limits<double>::quiet_NaN();
    /*!
     * \brief With an array (scene::array()): the target of interest's line-of-sight azimuth in rad
     *        (array_geometry.h's frame, 0 on boresight). NaN without an array, where a direction
     *        changes nothing in the channel.
     */
    double azimuth_rad = std::numeric_limits<double>::quiet_NaN();
    /*! \brief With an array: its line of sight's elevation in rad. NaN without an array. */
    double elevation_rad = std::numeric_limits<double>::quiet_NaN();
    int n_paths = 0;          ///< all paths of the realization, clutter included
    std::string micro_motion = "none"; ///< the target of interest's micro-motion model ("none", "sinusoid", "rotor", ...)
    /*!
     * \brief The track the frame belongs to: a tracked random scene's track index; a per-frame
     *        random scene's frame index (every frame its own track); 0 for a fixed scene.
     */
    uint64_t track_id = 0;
    uint64_t frame_in_track = 0; ///< frames of the track before this one (0: its first; a fixed scene: the frame index)
};

/*!
 * \brief The streams an array receives: one per receive and transmit element pair,
 *        receive-element-major (stream k·N_t + j: receive element k, transmit element j).
 * \param a the array.
 * \return N_r·N_t elements.
 */
SEMS_API std::vector<array_element> virtual_elements(const array_geometry& a);

/*! \brief One drawn frame: its paths and its truth. */
struct SEMS_API frame_realization {
    std::vector<channel_path> paths;     ///< every path, clutter included
    std::vector<scatterer_body> bodies;  ///< the scatterer bodies the paths refer to (channel_path::body)
    int truth_body = -1;                 ///< the target of interest's body (-1: none)
    frame_truth truth;                   ///< the target of interest
    /*!
     * \brief The frame's own slow-time clock, when it has one: a track's row 0 is at symbol
     *        frame_in_track·N of the track. Empty: row 0 is at the absolute index the caller
     *        passes (frame·N in a stream). frame_channel and td_channel use this when set.
     */
    std::optional<uint64_t> clock_symbol;
};

/*! \brief The separable factors of one frame: H[n,m] = Σ_l slow_l[n] · delay_l[m]. */
class SEMS_API frame_channel
{
public:
    /*!
     * \brief Computes the factors of one frame.
     * \param fs the frame settings.
     * \param paths the frame's paths.
     * \param first_symbol the absolute slow-time index of row 0.
     */
    frame_channel(const frame_settings& fs, const std::vector<channel_path>& paths, uint64_t first_symbol);
    /*!
     * \brief The factors of another frame, computed in place in the same buffers.
     * \details What a streaming block calls once per frame, allocation-free once the
     * buffers have grown.
     * \param paths the frame's paths.
     * \param first_symbol the absolute slow-time index of row 0.
     */
    void update(const std::vector<channel_path>& paths, uint64_t first_symbol);
    /*!
     * \brief The factors of a drawn frame, its scatterer bodies included.
     * \param r the frame (paths and bodies).
     * \param first_symbol the absolute slow-time index of row 0 (r.clock_symbol instead, when set).
     */
    void update(const frame_realization& r, uint64_t first_symbol);
    /*!
     * \brief A drawn frame's factors.
     * \param fs the frame settings. \param r the frame. \param first_symbol the absolute slow-time index of row 0 (r.clock_symbol instead, when set).
     */
    frame_channel(const frame_settings& fs, const frame_realization& r, uint64_t first_symbol);
    /*!
     * \brief A drawn frame's factors as one array element receives it: each path's gain turned by
     *        its steering phasor and pattern, its delay by the plane wave's delay at the element
     *        (steering.h). Later update() calls keep the element.
     * \param fs the frame settings. \param r the frame. \param first_symbol as above.
     * \param element the element.
     */
    frame_channel(const frame_settings& fs, const frame_realization& r, uint64_t first_symbol, const array_element& element);
    /*! \brief The element the factors are computed for. \return it (the origin by default). */
    const array_element& element() const { return d_element; }
    ~frame_channel(); ///< Destructor.
    /*! \brief Copy constructor. \param o the factors to copy. */
    frame_channel(const frame_channel& o);
    /*! \brief Move constructor. */
    frame_channel(frame_channel&&) noexcept;
    /*! \brief Copy assignment. \param o the factors to copy. \return *this. */
    frame_channel& operator=(const frame_channel& o);
    /*! \brief Move assignment. \return *this. */
    frame_channel& operator=(frame_channel&&) noexcept;

    /*! \brief N. \return the symbols per frame. */
    int n_symbols() const { return d_n; }
    /*! \brief M. \return the subcarriers per symbol. */
    int n_subcarriers() const { return d_m; }
    /*! \brief The number of separable terms (one per point path; a scatterer body's path has several, micro_motion.h). \return the terms. */
    int n_paths() const { return d_l; }

    /*! \brief One row of H. \param n the symbol. \param h out: h[m] = H[n,m], M values. */
    void row(int n, gr_complex* h) const;
    /*!
     * \brief Applies one row: y = H[n,:] ⊙ x.
     * \param n the symbol. \param x M input values. \param y M output values (may be x).
     */
    void apply_row(int n, const gr_complex* x, gr_complex* y) const;
    /*! \brief The whole frame's H. \param grid out: row-major N x M. */
    void fill(gr_complex* grid) const;

private:
    friend class array_channel;
    void update(const std::vector<channel_path>& paths, const std::vector<scatterer_body>* bodies, uint64_t first_symbol);
    void fill_delay_row(int row, double delay_s);
    void fill_body_rows(int row, double delay_s, const detail::expansion_plan& plan, double dk_scale, double dk);
    struct scratch; // scatterer bodies' plans and moments (lib/core/channel/channel_model.cc)
    frame_settings d_fs;
    array_element d_element;
    int d_n, d_m, d_l;
    std::vector<gr_complex> d_slow;  // N x L (a symbol's terms side by side), gain included
    std::vector<gr_complex> d_delay; // L x M (a scatterer body's path: its delay phasor and δk/δk_max)
    std::vector<double> d_delay_key; // per row: the delay (and term) its delay row was computed for
    std::unique_ptr<scratch> d_scratch;
};

struct body_share; // the scatterer bodies an array's elements share (lib/core/channel/channel_model.cc)

/*!
 * \brief One frame's factors at every stream of an array (virtual_elements()): what the array
 *        emulators compute once per frame.
 * \details Element k's factors equal frame_channel(fs, r, first_symbol, elements[k]); the
 * scatterer bodies' kinematics (a walker's pose, a rotor's blades) are taken once per frame and
 * shared, so an array of K elements costs K times the expansion and the rows, not K times the
 * bodies.
 */
class SEMS_API array_channel
{
public:
    /*!
     * \brief The factors of a frame format at an array's streams (empty until update()).
     * \param fs the frame settings. \param elements the streams (at least one).
     * \throws std::invalid_argument for no elements.
     */
    array_channel(const frame_settings& fs, const std::vector<array_element>& elements);
    ~array_channel(); ///< Destructor.
    /*! \brief Move constructor. */
    array_channel(array_channel&&) noexcept;
    /*! \brief Move assignment. \return *this. */
    array_channel& operator=(array_channel&&) noexcept;
    /*!
     * \brief Every element's factors of a drawn frame, in place.
     * \param r the frame. \param first_symbol the absolute slow-time index of row 0 (r.clock_symbol instead, when set).
     */
    void update(const frame_realization& r, uint64_t first_symbol);
    /*! \brief The streams. \return their number. */
    int n_elements() const { return static_cast<int>(d_channels.size()); }
    /*!
     * \brief One stream's factors.
     * \param k the stream, 0 .. n_elements() − 1.
     * \return its factors.
     * \throws std::invalid_argument beyond the streams.
     */
    const frame_channel& element(int k) const;

private:
    std::vector<frame_channel> d_channels;
    std::unique_ptr<body_share> d_share;
};

/*!
 * \brief The seeded channel model of one frame format and one scene: draws frames,
 *        their factors and the noise.
 */
class SEMS_API channel_model
{
public:
    /*!
     * \brief A model of a scene on a frame.
     * \param fs the frame settings.
     * \param sc the scene.
     * \param seed seed of the scene/gain draws and of the noise.
     * \throws std::invalid_argument if the scene does not fit the frame (ranges inside the
     *         unambiguous delay, instantaneous Doppler inside ±1/(2T)).
     */
    channel_model(const frame_settings& fs, const scene& sc, uint64_t seed);
    ~channel_model(); ///< Destructor.
    /*! \brief Move constructor. */
    channel_model(channel_model&&) noexcept;
    /*! \brief Move assignment. \return *this. */
    channel_model& operator=(channel_model&&) noexcept;

    /*! \brief The frame settings. \return the model's frame. */
    const frame_settings& settings() const { return d_fs; }
    /*! \brief The scene. \return the model's scene. */
    const scene& scene_spec() const { return d_scene; }

    /*!
     * \brief σ² for an SNR in dB.
     * \param snr_db SNR per resource element in dB (+inf: noiseless).
     * \return 10^(-snr_db/10); 0 for +inf.
     * \throws std::invalid_argument on NaN.
     */
    static double noise_variance(double snr_db);

    /*!
     * \brief Draws the next frame's paths (scene parameters for random scenes, and gains).
     * \details A tracked random scene (random_spec::tracks) goes on with its current track and
     * starts the next one (track index + 1; track 0 first) after the current one's last frame;
     * the frame index only names the frame in the truth.
     * \param frame_index the frame index written into the truth.
     * \return the frame's paths and truth.
     */
    frame_realization draw(uint64_t frame_index);
    /*!
     * \brief The same draw into `out`, reusing its buffers: what a streaming block calls once
     *        per frame, allocation-free once they have grown (fixed scenes are read in place).
     * \param frame_index the frame index written into the truth.
     * \param out the frame's paths and truth.
     */
    void draw(uint64_t frame_index, frame_realization& out);
    /*!
     * \brief The frame's separable factors.
     * \param r a drawn frame.
     * \param first_symbol the absolute slow-time index of row 0 (r.clock_symbol instead, when set).
     * \return the factors.
     * \throws std::invalid_argument when the scene's array gives more than one stream (then
     *         name the element: the overload below).
     */
    frame_channel factors(const frame_realization& r, uint64_t first_symbol) const;
    /*!
     * \brief The frame's factors at one element of the scene's array (virtual_elements()).
     * \param r a drawn frame. \param first_symbol as above.
     * \param element the stream: 0 .. n_elements() − 1.
     * \return the factors.
     * \throws std::invalid_argument for an element beyond the array.
     */
    frame_channel factors(const frame_realization& r, uint64_t first_symbol, int element) const;
    /*! \brief The streams the scene's array receives (1 without an array). \return N_r·N_t. */
    int n_elements() const { return static_cast<int>(d_elements.size()); }
    /*! \brief Those streams (virtual_elements(); the origin without an array). \return them. */
    const std::vector<array_element>& elements() const { return d_elements; }

    /*!
     * \brief Adds noise: y += CN(0, σ²) per element; draws nothing when snr_db = +inf.
     * \details The noise is a single-precision vectorised Box–Muller stream
     * (lib/core/kernels/gaussian_generator.h): the same seed gives the same noise whatever the sizes
     * of the calls.
     * \param y the values to add noise to.
     * \param count the number of values.
     * \param snr_db SNR per resource element in dB.
     */
    void add_noise(gr_complex* y, size_t count, double snr_db);

    /*!
     * \brief Noiseless H of consecutive frames.
     * \param count frames to generate.
     * \param h_out out: count x N x M values.
     * \param first_frame index of the first frame (its rows start at first_frame·N).
     * \return the frames' truths.
     */
    std::vector<frame_truth> generate(size_t count, gr_complex* h_out, uint64_t first_frame = 0);

    /*!
     * \brief Starts track `track_index` of a tracked random scene: the next draw() gives its
     *        first frame. Its targets, gains and length are a function of (seed, track index)
     *        alone, so any track is drawn without the ones before it.
     * \param track_index the track.
     * \return its length in frames: its planned K, cut at its last frame inside the range bounds.
     * \throws std::logic_error when the scene has no tracks.
     */
    int begin_track(uint64_t track_index);

    /*! \brief Restarts both generators (and a tracked scene at track 0). \param seed the new seed. */
    void reseed(uint64_t seed);

private:
    struct rngs; // generators and per-frame scratch (lib/core/channel/channel_model.cc)
    frame_settings d_fs;
    scene d_scene;
    std::vector<array_element> d_elements; // the scene's array's streams (the origin without one)
    std::unique_ptr<rngs> d_rng;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_CHANNEL_MODEL_H */
