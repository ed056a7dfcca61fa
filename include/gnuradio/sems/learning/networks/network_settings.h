// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Sizes of the learning networks (docs/design.md §5), the one place their defaults live.
 *
 * \details Torch-free on purpose: the trainer settings, bundle.json and the Python bindings carry
 * these structs without pulling in LibTorch. Users trade speed for accuracy here
 * (width, depth, dictionary size Q).
 */
#ifndef INCLUDED_SEMS_LEARNING_NETWORK_SETTINGS_H
#define INCLUDED_SEMS_LEARNING_NETWORK_SETTINGS_H

#include <gnuradio/sems/learning/api.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gr {
namespace sems {
/*! \brief Settings of the learning networks (Torch-free). */
namespace nn {

/// Semantic encoder: which N_p of the N x M resource elements carry pilots (semantic_encoder.h).
//
/// Two kinds, the setting `kind`:
///  - "gumbel_topk" (the default): deep probabilistic subsampling. One score matrix with
///    symbol x subcarrier structure, Z[n,m] = a[n] + b[m] (+ a free N x M term with
///    free_scores); each step draws the N_p largest of Z + Gumbel noise, which are N_p
///    distinct elements by construction (no collision penalty needed), and back-propagates
///    through N_p sequential relaxed softmax draws (each over the elements not yet taken).
///  - "gumbel_heads": the paper's N_p Gumbel-Softmax heads (an MLP per-head embedding ->
///    scores, see `embedding`, `hidden`, `factorized`, `shared`), kept for comparison;
///    distinctness comes from the final greedy assignment (and, optionally, the collision
///    penalty, which by default is off: it forbids pilots sharing a subcarrier while the
///    heads still agree, exactly the structure Doppler needs).
/// Both use hard (exact 0/1) masks in the forward pass from the first step unless
/// soft_epochs > 0.
struct SEMS_LEARNING_API encoder_settings {
    std::string kind = "gumbel_topk"; ///< "gumbel_topk" | "gumbel_heads"
    bool free_scores = false;    ///< gumbel_topk: add a free N x M score term to a[n] + b[m]
    int embedding = 16;          ///< gumbel_heads: learned embedding per head
    int hidden = 64;             ///< gumbel_heads: MLP hidden width (embedding -> hidden -> scores)
    double temperature_start = 2.0; ///< relaxation temperature of the backward pass
    double temperature_floor = 0.1; ///< annealing never goes below this
    double temperature_decay = 0.8;  ///< per epoch: tau <- max(floor, tau * decay)
    int soft_epochs = 0;             ///< the first soft_epochs mask epochs feed the decoder the
                                     /// relaxed (soft, dense) selection; afterwards, and always
                                     /// when 0 (the default), the forward pass is the exact
                                     /// hard 0/1 mask and only the gradient is relaxed
    double collision_weight = 0.0;   ///< gumbel_heads: penalty on two heads wanting the same
                                     /// element (0 = off; gumbel_topk never collides)
    bool factorized = true;          ///< gumbel_heads: Z_r[n,m] = a_r[n] + b_r[m] (the MLP emits
                                     /// N + M scores per head); false: a free N*M matrix per head
    bool shared = false;             ///< gumbel_heads: add one shared score matrix (from an extra
                                     /// embedding) to every head's
    double lr_scale = 30.0;          ///< encoder learning rate = lr * lr_scale: the scores must
                                     /// sharpen within a few epochs (annealing the temperature
                                     /// cannot: argmax(Z + g) follows softmax(Z) at any τ)

    /*! \brief Whether `k` names an encoder. \param k the name. \return true for "gumbel_topk" or "gumbel_heads". */
    static bool known_kind(const std::string& k) { return k == "gumbel_topk" || k == "gumbel_heads"; }
    /*! \brief The settings as JSON (every key). \return the JSON object from_json() reads. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; a missing key takes its legacy value (the one bundles
     *        written before the key existed were trained with, noted per member), else its default.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static encoder_settings from_json(const nlohmann::json& j, const std::string& source);
};

/// Classifier decoder. Two architectures, the setting `architecture`:
///  - "spectral" (the default, spectral_classifier_decoder.h): phase-invariant Doppler
///    power profile of the pilots on any mask, an optional zero-Doppler (MTI) stage,
///    1-D CNN over Doppler bins -> MLP -> features -> C;
///  - "resnet" (classifier_decoder.h, the paper's): sparse 2 x N x M grid -> 2-D ResNet
///    -> MLP -> features -> C.
struct SEMS_LEARNING_API classifier_settings {
    std::string architecture = "spectral"; ///< "spectral" | "resnet"
    int n_classes = 3;   ///< C, the decoder's outputs
    int width = 16;      ///< channels of the convolutions (both architectures)
    int depth = 2;       ///< resnet: residual blocks (3 x 1 along slow time)
    int hidden = 64;     ///< MLP hidden width
    int features = 16;   ///< the embedding the t-SNE looks at
    int doppler_bins = 64;  ///< spectral: slow-time DFT size K (>= N; zero-filled beyond N)
    int kernel = 5;         ///< spectral: 1-D kernel over Doppler bins (odd)
    int range_bins = -1;    ///< spectral: the range gate, a DFT across subcarriers into L delay
                            /// bins and the Doppler profile of the strongest bin (coherent over
                            /// subcarriers, as a radar range-gates before Doppler processing).
                            /// Exact on a one-subcarrier mask; on pilots spread over several
                            /// subcarriers the search over L bins costs at low SNR, which steers
                            /// the mask learner to the one-subcarrier structure classification
                            /// needs (docs/RESULTS.md). L > 0 bins; -1 = 2·M (resolved by the
                            /// decoder: half-bin delay steps); 0 = no gate, the subcarriers'
                            /// Doppler profiles summed in power (the legacy value for bundles
                            /// without this key)
    double conv_slope = 0.1; ///< spectral: negative slope of the convolutions' activations (leaky
                             /// ReLU): a cold start on uninformative random masks cannot kill
                             /// every unit (with 0, plain ReLU, the legacy value for bundles
                             /// without this key, some seeds never left chance)
    std::string mti = "none"; ///< spectral: zero-Doppler stage, "none" | "mean" (each subcarrier
                              /// minus its mean over its observed symbols: removes static
                              /// clutter exactly, and with it a target at 0 Hz) | "both"
                              /// (the two profiles as two input channels)
    int chirp_bins = 9;       ///< spectral: the tone/chirp fit, J chirp rates (odd; 0 = off, the legacy
                              /// value for bundles without this key): the share of the energy of
                              /// the subcarriers' slow-time series that one common chirp
                              /// exp(j(2π f n + π α_j (n - (N-1)/2)²)) explains, maximised over f off
                              /// the DFT grid, per rate, as log(1 - share + 1e-4) through its own
                              /// layer of `features` units. A car is a pure tone (share 1 at
                              /// α = 0), a pedestrian's limb swing a chirp within one frame: at
                              /// equal Doppler their power profiles are alike, this is not
                              /// (docs/RESULTS.md, the any-heading scene)
    double chirp_sweep_bins = 2.0; ///< spectral: the largest rate's Doppler change across the frame,
                                   /// in Doppler bins (1/(N T)); the rates spread evenly over ±it
    int chirp_min_pilots = 3; ///< spectral: the tone/chirp fit counts only the subcarriers with at
                              /// least this many pilots (1 = every observed one, the legacy value
                              /// for bundles without this key). On one or two pilots some chirp
                              /// fits any series exactly, so such subcarriers report "explained"
                              /// whatever the target is, and a mask learner drifts to masks of one
                              /// to three symbols across many subcarriers, where the fit says
                              /// nothing (docs/results/notes/tone_fit.md, the collapsed no-micro-Doppler seed)
    int template_frames = 0;  ///< spectral: the template bank, T of the training frames' noiseless
                              /// pilots on the final mask, kept in the decoder (0 = off, the
                              /// legacy value for bundles without this key; -1 = every training
                              /// frame, resolved by the trainer and recorded as the count). Each frame is matched
                              /// against every template by its normalised correlation ρ_t, and each
                              /// class scores log mean_t exp(β ρ_t) over its templates, with
                              /// β = N_p / (1 - max_t ρ_t) estimated from the frame itself (no SNR
                              /// given): the Monte-Carlo Bayes classifier of the training frames
                              /// under an unknown complex gain. A layer joins those scores to the
                              /// network's logits. The templates are set when the mask is final
                              /// (the decoder phase), matched leave-one-out while training. Cost per
                              /// frame: 8·N_p·T multiply-adds, and 8·N_p·T bytes in decoder.pt
                              /// (docs/PERFORMANCE.md)

    /*! \brief Whether `a` names an architecture. \param a the name. \return true for "spectral" or "resnet". */
    static bool known_architecture(const std::string& a) { return a == "spectral" || a == "resnet"; }
    /*! \brief Whether `m` names an MTI stage. \param m the name. \return true for "none", "mean" or "both". */
    static bool known_mti(const std::string& m) { return m == "none" || m == "mean" || m == "both"; }
    /*!
     * \brief Checks every value that does not depend on the frame (one check for the bundle
     * reader and the decoder's constructor).
     * \param source names the file or context in errors ("source: key: problem").
     * \throws std::invalid_argument naming the setting and the value.
     */
    void validate(const std::string& source) const;
    //! The tone/chirp fit's rates α_j in cycles per symbol² (chirp_bins of them, 0 in the middle).
    //! \param n_symbols N (>= 1). \return the rates, ascending.
    //! \throws std::invalid_argument for n_symbols < 1.
    std::vector<double> chirp_rates(int n_symbols) const;
    /*! \brief The settings as JSON (the keys of its architecture; template_frames only when not 0). \return the JSON object from_json() reads. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; a missing key takes its legacy value (the one bundles
     *        written before the key existed were trained with, noted per member), else its default.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static classifier_settings from_json(const nlohmann::json& j, const std::string& source);
};

/// Delay decoder: time projection -> dictionary correlation -> dilated 1-D ResNet ->
/// local soft-argmax -> (optional) model-based refinement of the first path.
/// Bundles written before a key existed load with its legacy value (noted per key), so
/// they compute exactly what they computed when they were trained.
struct SEMS_LEARNING_API delay_settings {
    double tau_min_index = -2.0;  ///< dictionary grid, in delay indices (tau * B)
    double tau_max_index = 50.0;  ///< upper end of the dictionary grid
    int q = 417;                  ///< grid points; spacing = (max - min) / (q - 1)
    int projections = 2;          ///< complex time projections (2 -> the 4 x M of the paper)
    int width = 16;               ///< 1-D CNN channels
    int depth = 6;                ///< residual blocks
    int kernel = 3;               ///< 1-D kernel (odd)
    int dilation_growth = 2;      ///< block i dilates by growth^i (1, 2, 4, ...): the receptive
                                  /// field grows exponentially with depth; 1 = undilated
                                  /// (legacy value for bundles without this key)
    bool phase_reference = true;  ///< rotate the correlations so the strongest one is real: the
                                  /// features become invariant to the frame's common phase
                                  /// (legacy: false)
    int residual_maps = 2;        ///< extra feature maps: |correlation| of the residual after
                                  /// removing the 1..K strongest dictionary atoms (orthogonal
                                  /// matching pursuit on the first projection): a weak first
                                  /// path under a strong later path's sidelobes shows up there
                                  /// (legacy: 0)
    int window = 8;               ///< local soft-argmax half-window (grid points); 0 = global
    int refine_paths = -1;        ///< model-based refinement after the network: L paths fitted by
                                  /// least squares, the first one started at the network's
                                  /// estimate (see delay_decoder.h); 0 = off (legacy value);
                                  /// -1 = the training scene's paths per target, or 0 when the
                                  /// pilots are too few for them, 2·N_p <= 3L + 1 (the trainer
                                  /// resolves it; a decoder refuses an unresolved -1)
    double refine_span_index = -1.0; ///< later paths are searched in (tau1 + 0.25, tau1 + span];
                                     /// -1 = the training scene's largest excess delay + 1
                                     /// (resolved by the trainer, like refine_paths); 8 (legacy
                                     /// value: a bundle without the key)
    double refine_trust_index = 0.5; ///< the refined delay replaces the network's only when it
                                     /// moved less than this
    bool refine_global_peak = true;  ///< single-path refinement (refine_paths = 1): when the
                                     /// strongest dictionary correlation lies farther than
                                     /// refine_trust_index from the network's estimate, a
                                     /// second fit starts there, and the fit that explains
                                     /// the pilots better (smaller residual: the maximum-
                                     /// likelihood choice) wins (legacy: false)
    double refine_global_min_fraction = 0.0; ///< the second start runs only when a model
                                             /// explains at least this share of the pilots'
                                             /// energy (0 = always): with one path the one-path
                                             /// model at the grid peak (noise alone reaches
                                             /// ~ln(cells)/N_p at its strongest delay, 0.12
                                             /// for 32 pilots over 44 delay indices: a fast
                                             /// decoder skips frames with no clear peak); with
                                             /// several (refine_global_fit) the decoder's own
                                             /// refined fit (a low-SNR frame, where the
                                             /// reference is far worse than the network)
    bool refine_global_fit = true; ///< multipath refinement (refine_paths = L > 1): the
                                   /// oracle-order least-squares fit (L paths, grid search on
                                   /// the decoder's dictionary grid, then nonlinear least
                                   /// squares: ls_delay_estimator) is a second start, and its
                                   /// earliest delay wins when it lowers the residual by more
                                   /// than 20 noise variances and differs by more than a
                                   /// quarter index — the multipath
                                   /// counterpart of refine_global_peak. Costs ~0.7 ms per
                                   /// frame on one core (legacy: false)

    /*! \brief The grid spacing. \return (tau_max_index - tau_min_index) / (q - 1) delay indices. */
    double spacing() const { return (tau_max_index - tau_min_index) / (q - 1); }
    /*! \brief Receptive field of one output score: the stem and two convolutions per residual
     *         block, block i with dilation dilation_growth^i. \return the width in grid points. */
    int receptive_field_points() const;
    /*! \brief The receptive field in delay indices. \return points x spacing. */
    double receptive_field_index() const { return receptive_field_points() * spacing(); }
    /*! \brief The settings as JSON (as bundle.json records them). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; a missing key takes its legacy value (the one bundles
     *        written before the key existed were trained with, noted per member), else its default.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static delay_settings from_json(const nlohmann::json& j, const std::string& source);
};

/*! \brief Channel reconstruction decoder (the MSE-objective baseline). */
struct SEMS_LEARNING_API reconstruction_settings {
    int hidden = 256; ///< MLP hidden width

    /*! \brief The settings as JSON (as bundle.json records them). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static reconstruction_settings from_json(const nlohmann::json& j, const std::string& source);
};

/*!
 * \brief The angle decoder of a position bundle (learning/array/angle_network.h): the
 *        beamforming spectrum of an array's pilots on a grid of azimuths, a 1-D residual CNN over
 *        it, a local soft-argmax, then the spectrum's own maximum near that estimate.
 */
struct SEMS_LEARNING_API angle_settings {
    int grid = 128;                ///< Q, azimuths of the spectrum, evenly spaced over [azimuth_min_rad, azimuth_max_rad]
    double azimuth_min_rad = -1.0; ///< the grid's first azimuth (≥ −π/2)
    double azimuth_max_rad = 1.0;  ///< its last (≤ π/2, > azimuth_min_rad)
    int channels = 32;             ///< CNN width
    int blocks = 4;                ///< residual blocks; block i dilates by 2^i
    int kernel = 5;                ///< odd kernel size
    int window = 6;                ///< soft-argmax: ±window grid points around the arg-max (0: global)
    /*!
     * \brief The polish: the beamforming spectrum's maximum within ±polish_steps grid steps of the
     *        network's estimate, kept only when it lies inside that interval (0: no polish).
     */
    double polish_steps = 1.0;

    /*! \brief Checks the values. \param source names the context. \throws std::invalid_argument naming the key. */
    void validate(const std::string& source) const;
    /*! \brief The settings as JSON (every key). \return the JSON object from_json() reads. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings (validated).
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static angle_settings from_json(const nlohmann::json& j, const std::string& source);
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_NETWORK_SETTINGS_H */
