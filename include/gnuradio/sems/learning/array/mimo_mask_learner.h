// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Learning a MIMO mask (core/array/mimo_mask.h): which N_p resource elements carry
 *        pilots and which transmit element sends each, for a target's azimuth
 *        (docs/reference/arrays.md, "MIMO masks").
 *
 * \details Torch-free header (the app and the evaluation call it). The objective is the
 * azimuth's Cramér–Rao bound with the target's delay, Doppler and complex gain unknown
 * (baselines/mimo_angle.h), averaged over the azimuths the scene draws (uniform on
 * [azimuth_min_rad, azimuth_max_rad]): the mean squared error an efficient estimator reaches
 * there, which the maximum-likelihood estimator does at high SNR. Its Fisher information is a
 * closed form in the mask, so the learner needs no frames and no decoder: it is the bound
 * itself that is minimised, over
 *  - the resource elements: the semantic encoder's Gumbel top-k (exactly N_p distinct
 *    resource elements forward, relaxed gradient; the frame's guards excluded);
 *  - each element's transmit element: one logit per transmit element and resource element,
 *    a straight-through Gumbel-softmax (one element forward, relaxed gradient).
 * Each step draws `draws` azimuths from the scene's interval and minimises log(mean CRB); the
 * temperature is annealed per epoch; the kept mask is the epoch's final (greedy) mask with the
 * lowest objective on a fixed grid of azimuths. A polish ends it: single changes of one pilot
 * (its transmit element, or a move to a free neighbouring resource element), each kept when it
 * lowers that objective, until none does (the relaxation settles on balanced shares slowly when
 * each element has a handful of pilots). Every pilot is sent by one element at full
 * energy (the hand form "same pilots", every element at 1/sqrt(N_t), is a reference it is
 * compared against, not a choice it makes).
 */
#ifndef INCLUDED_SEMS_LEARNING_MIMO_MASK_LEARNER_H
#define INCLUDED_SEMS_LEARNING_MIMO_MASK_LEARNER_H

#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Everything learn_mimo_mask() needs. */
struct SEMS_LEARNING_API mimo_mask_settings {
    std::string array = "mimo2x4_3g"; ///< the array: a preset's name or an array file (N_t ≥ 2)
    frame_settings frame;             ///< the frame
    int n_pilots = 32;                ///< N_p
    double azimuth_min_rad = -0.8;    ///< the scene's azimuths: lower end
    double azimuth_max_rad = 0.8;     ///< upper end
    double elevation_rad = 0.0;       ///< the targets' elevation
    int epochs = 40;                  ///< epochs
    int steps = 25;                   ///< steps per epoch
    int draws = 64;                   ///< azimuths per step
    int eval_azimuths = 161;          ///< the fixed grid the kept mask is chosen on
    double lr = 0.01;                 ///< base learning rate: Adam's is lr · encoder.lr_scale, for the resource elements' and the transmit elements' scores alike
    nn::encoder_settings encoder;     ///< the resource elements' selector and its temperature schedule
    uint64_t seed = 1;                ///< seed of the draws and the initial scores
    int threads = 0;                  ///< <= 0: leave LibTorch's default
    std::string command_line;         ///< recorded in the mask's origin
    bool verbose = true;              ///< per-epoch progress on the log

    /*! \brief Checks every setting. \throws std::invalid_argument naming the setting. */
    void validate() const;
};

/*! \brief What learn_mimo_mask() returns. */
struct SEMS_LEARNING_API mimo_mask_result {
    mimo_mask mask;            ///< the kept mask, polished
    nlohmann::json history;    ///< one object per epoch
    double mean_crb_rad2 = 0;  ///< its objective: the mean CRB over eval_azimuths at an SNR of 1 per pilot
    double mean_crb_learned_rad2 = 0; ///< the objective of the gradient phase's mask, before the polish
    int polish_changes = 0;    ///< the single changes the polish kept
    double seconds = 0.0;      ///< wall time
};

/*!
 * \brief The objective: the mean of mimo_angle_crb_rad2 at an SNR of 1 (0 dB) per pilot and
 *        receive element over `count` azimuths at the midpoints of equal cells of [lo, hi].
 * \details At SNR s the mean bound is this over s. +inf when the mask cannot tell the angle at
 * one of them.
 * \param a the array. \param m the mask. \param fs the frame. \param lo the interval's lower end. \param hi its upper end.
 * \param count azimuths (≥ 1). \param elevation_rad θ.
 * \return the mean in rad².
 */
SEMS_LEARNING_API double mimo_mean_crb_rad2(const array_geometry& a, const mimo_mask& m, const frame_settings& fs,
                                            double lo, double hi, int count, double elevation_rad = 0.0);

/*!
 * \brief The floor of mimo_mean_crb_rad2 for masks whose pilots each come from one element: the
 *        virtual array's bound (angle_crb_rad2) with N_p/N_t pilots per virtual element, the delay
 *        and Doppler known, at the highest subcarrier's wavelength (the largest electrical
 *        aperture any pilot has), averaged over the same azimuths.
 * \param a the array. \param fs the frame. \param n_pilots N_p. \param lo the interval's lower end.
 * \param hi its upper end. \param count azimuths (≥ 1). \param elevation_rad θ.
 * \return the mean in rad² at 0 dB per pilot.
 */
SEMS_LEARNING_API double mimo_floor_crb_rad2(const array_geometry& a, const frame_settings& fs, int n_pilots,
                                             double lo, double hi, int count, double elevation_rad = 0.0);

/*!
 * \brief The learner's polish alone, from any mask: single changes of one pilot (its transmit
 *        element, or a move to a free neighbouring resource element), each kept when it lowers
 *        the objective (mimo_mean_crb_rad2 over the settings' azimuths), until none does.
 * \details The reference that tells what the gradient phase adds: the same polish from a
 * random mask.
 * \param m the start (the settings' frame and array's N_t). \param s the settings (array, frame,
 *        azimuths). \param objective out (may be null): the polished mask's mean bound.
 * \param changes out (may be null): the changes kept.
 * \return the polished mask.
 * \throws std::invalid_argument naming a bad setting, or the mask's N_t or grid when they are not the settings'.
 */
SEMS_LEARNING_API mimo_mask polish_mimo_mask(const mimo_mask& m,
                                             const mimo_mask_settings& s,
                                             double* objective = nullptr,
                                             int* changes = nullptr);

/*!
 * \brief Learns a MIMO mask (the file comment).
 * \param s the settings (validated first).
 * \param log where progress goes (nullptr: silent).
 * \return the mask, its history and objective.
 * \throws std::invalid_argument naming a bad setting or file.
 */
SEMS_LEARNING_API mimo_mask_result learn_mimo_mask(const mimo_mask_settings& s, std::ostream* log);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_MIMO_MASK_LEARNER_H */
