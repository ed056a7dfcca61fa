// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Sizes of the learning networks (DESIGN §5), the one place their defaults live.
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

namespace gr {
namespace sems {
/*! \brief Settings of the learning networks (Torch-free). */
namespace nn {

/*! \brief Semantic encoder: N_p Gumbel-Softmax heads over the N x M grid. */
struct SEMS_LEARNING_API encoder_settings {
    int embedding = 16;          ///< learned embedding per head
    int hidden = 64;             ///< MLP hidden width (embedding -> hidden -> N*M scores)
    double temperature_start = 2.0; ///< initial Gumbel-Softmax temperature τ
    double temperature_floor = 0.1; ///< annealing never goes below this
    double temperature_decay = 0.8;  ///< per epoch: tau <- max(floor, tau * decay)
    double soft_above = 1.0;         ///< while tau > this the forward pass uses the soft selection
                                     ///< (a dense weighted grid the decoder can learn from first);
                                     ///< at or below it, the straight-through exact one-hot
    double collision_weight = 5.0;   ///< penalty on two heads wanting the same element
    bool factorized = true;          ///< Z_r[n,m] = a_r[n] + b_r[m] (the MLP emits N + M scores per
                                     ///< head): a head's symbol and subcarrier preferences each
                                     ///< gather gradient over a whole row/column, which learns
                                     ///< structured patterns (shared subcarriers or symbols) in
                                     ///< few epochs; false: a free N*M score matrix
    bool shared = false;             ///< add one shared score matrix (from an extra embedding)
                                     ///< to every head's: heads can agree on a subcarrier or
                                     ///< symbol while the collision penalty keeps them apart
    double lr_scale = 1.0;           ///< encoder learning rate = lr * lr_scale

    /*! \brief The settings as JSON (as bundle.json records them). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static encoder_settings from_json(const nlohmann::json& j, const std::string& source);
};

/*! \brief Classifier decoder: sparse 2 x N x M grid -> 2-D ResNet -> MLP -> 16 -> C. */
struct SEMS_LEARNING_API classifier_settings {
    int n_classes = 3;   ///< C
    int width = 16;      ///< channels of the stem and the residual blocks
    int depth = 2;       ///< residual blocks (3 x 1 along slow time)
    int hidden = 64;     ///< MLP hidden width
    int features = 16;   ///< the embedding the t-SNE looks at

    /*! \brief The settings as JSON (as bundle.json records them). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static classifier_settings from_json(const nlohmann::json& j, const std::string& source);
};

/*! \brief Delay decoder: time projection -> dictionary correlation -> 1-D ResNet -> soft-argmax. */
struct SEMS_LEARNING_API delay_settings {
    double tau_min_index = -2.0;  ///< dictionary grid, in delay indices (tau * B)
    double tau_max_index = 50.0;  ///< upper end of the dictionary grid
    int q = 417;                  ///< grid points; spacing = (max - min) / (q - 1)
    int projections = 2;          ///< complex time projections (2 -> the 4 x M of the paper)
    int width = 8;                ///< 1-D CNN channels
    int depth = 2;                ///< residual blocks
    int kernel = 5;               ///< 1-D kernel
    int window = 8;               ///< local soft-argmax half-window (grid points); 0 = global

    /*! \brief The grid spacing. \return (tau_max_index - tau_min_index) / (q - 1) delay indices. */
    double spacing() const { return (tau_max_index - tau_min_index) / (q - 1); }
    /*! \brief The settings as JSON (as bundle.json records them). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
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

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_NETWORK_SETTINGS_H */
