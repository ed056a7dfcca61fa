// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier decoder (docs/design.md §5), the default classifier.
 *
 *   pilots on any mask: sparse B x 2 x N x M grid (zero off the mask) and the N x M
 *   (or B x N x M) mask
 *   -> per-frame normalisation (unit mean pilot power, normalise_frames)
 *   -> zero-Doppler (MTI) stage, classifier_settings::mti:
 *        "none": the observations as they are;
 *        "mean": y[n,m] - P[n,m] · (Σ_n' P[n',m] y[n',m]) / c_m with c_m the pilots on
 *                subcarrier m: every static (zero-Doppler) path is removed exactly, static
 *                clutter included (and with it a target at exactly 0 Hz); a subcarrier with
 *                one pilot becomes zero;
 *        "both": the two profiles below as two input channels;
 *   -> slow-time DFT per subcarrier, zero-filled to K = doppler_bins bins:
 *        F[k,m] = Σ_n y[n,m] exp(-j2π k n / K),   S[k] = Σ_m |F[k,m]|²
 *      or, with a range gate (classifier_settings::range_bins = L > 0, the default 2·M),
 *      coherently across subcarriers: R[k,l] = Σ_m F[k,m] exp(+j2π m l / L),
 *        l* = argmax_l Σ_k |R[k,l]|²,   S[k] = |R[k,l*]|²  (the target's delay bin;
 *      on subcarriers that share no symbol the energy is the same in every bin, by
 *      Parseval, and the first maximum as rounded decides: the gate is meant for masks
 *      whose subcarriers overlap in slow time, and exact on one subcarrier); R is a
 *      product with the M x L phasors below 128 subcarriers, an inverse FFT from there on
 *   -> x[k] = log(S[k] / mean_k S + 1e-3)
 *   -> BatchNorm -> two circular 1-D convolutions over the K bins (width channels,
 *      kernel, leaky ReLU of slope conv_slope) -> MLP (hidden) -> features -> C logits.
 *   -> beside the profile, with classifier_settings::chirp_bins = J > 0, the tone/chirp
 *      fit of the subcarriers' slow-time series y_m[n] (after MTI where there is one): per
 *      rate α_j the share of their energy one common chirp explains,
 *        E_j = max_f Σ_m |Σ_n y[n,m] exp(-j(2π f n + π α_j (n-(N-1)/2)²))|² / Σ_m n_m Σ_n |y[n,m]|²
 *      in [0, 1] (n_m: the pilots on subcarrier m; 1 iff every subcarrier's series is that
 *      chirp, with any gain and phase of its own, so exact on any mask), f searched off the
 *      DFT grid from the profile's peak (two parabolic steps); log(1 - E_j + 1e-4)
 *      -> BatchNorm -> a layer of `features` units -> joined to the profile's hidden layer.
 *
 * Why: the class lives in slow time (Doppler, micro-Doppler). |F[k,m]|² does not depend
 * on the target's delay phase (a constant per subcarrier) nor on its gain phase, and the
 * sum over subcarriers uses every pilot of any mask (the range gate sums them coherently at
 * the target's delay bin; on one subcarrier it changes nothing, on several its search over
 * the delay bins costs at low SNR, so a mask learned through it keeps its pilots on one
 * subcarrier: the Doppler structure, found from a cold start), so the same network trains on the
 * encoder's changing masks and decodes a fixed one. The DFT is a fixed matrix (not learned,
 * not stored in decoder.pt). Cost per frame: N·K·M multiply-adds for the DFT, then a
 * network of about width·K·hidden weights; the tone fit adds 7 evaluations of J chirps on
 * every occupied subcarrier (7·J·N sines and cosines, 28·J·N·M' multiply-adds per frame).
 * Why the tone fit: a car is a pure tone in slow time, a walking pedestrian's limb swing a
 * chirp within one 32 ms frame. Where their bulk Doppler overlaps (targets that do not
 * approach head on) the power profile on a 64-bin grid cannot tell them apart: a tone
 * between two bins loses up to 19 % of its peak, more than a pedestrian's chirp does. The
 * share one tone (or chirp) explains, maximised off the grid, is 1 for a noiseless car.
 *
 *   -> beside them, with classifier_settings::template_frames = T > 0, the template bank
 *      (template_bank.h): the pilots matched against T noiseless training frames, one class
 *      score each, through a layer added to the logits (once the bank is filled).
 */
#ifndef INCLUDED_SEMS_LEARNING_SPECTRAL_CLASSIFIER_DECODER_H
#define INCLUDED_SEMS_LEARNING_SPECTRAL_CLASSIFIER_DECODER_H

#include "learning/networks/task_decoder.h"
#include "learning/networks/template_bank.h"
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <mutex>
#include <utility>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

/*!
 * \brief Subtract each subcarrier's mean over its observed symbols (the MTI stage).
 * \param grid B x 2 x N x M pilot grid, zero off the mask (as every decoder input is).
 * \param mask N x M or B x N x M, 1 at pilots.
 * \return the grid with every static (zero-Doppler) component removed at the pilots, zero elsewhere.
 */
SEMS_LEARNING_API torch::Tensor remove_zero_doppler(const torch::Tensor& grid, const torch::Tensor& mask);

class SEMS_LEARNING_API spectral_classifier_decoder_module : public task_decoder_module
{
public:
    spectral_classifier_decoder_module(int n_symbols, int n_subcarriers, int n_pilots, classifier_settings s);
    //! Without a mask: refused (the MTI stage and the pilot count need it).
    decoder_output forward(const torch::Tensor& grid) override;
    decoder_output forward(const torch::Tensor& grid, const torch::Tensor& mask) override;
    //! The same on a compact grid whose columns are the subcarriers `columns` (given per call,
    //! not kept: a super-frame's sets each have their own; bundle_decoder).
    decoder_output forward(const torch::Tensor& grid, const torch::Tensor& mask, const torch::Tensor& columns);
    //! The B x channels x K log Doppler profile the network sees (before BatchNorm).
    torch::Tensor profile(const torch::Tensor& grid, const torch::Tensor& mask) const;
    //! The B x J tone/chirp-fit features log(1 - E_j + 1e-4) (undefined when chirp_bins = 0).
    torch::Tensor tone_features(const torch::Tensor& grid, const torch::Tensor& mask) const;
    std::string kind() const override { return "classifier_spectral"; }
    nlohmann::json describe() const override;
    const classifier_settings& settings() const { return d_s; }
    //! The subcarriers of a compact grid's columns (bundle_decoder's input: the mask's
    //! occupied subcarriers only, in increasing order); the range gate needs them.
    void set_compact_columns(const std::vector<int64_t>& subcarriers);
    //! The template bank (nullptr when template_frames = 0).
    std::shared_ptr<template_bank_module> template_bank() const { return d_templates; }

private:
    // cols: the subcarriers of grid's columns (undefined: all M).
    torch::Tensor power_profile(const torch::Tensor& grid, const torch::Tensor& cols) const;
    // The tone/chirp fit's B x J features log(1 - share + 1e-4), searched from the peak of
    // `profile` (that stage's B x 1 x K log profile).
    torch::Tensor tone_fit(const torch::Tensor& grid, const torch::Tensor& mask, const torch::Tensor& profile) const;
    // The B x 2 x N_p pilots of a grid (whole or compact) in its mask's order, for the template bank.
    torch::Tensor template_observations(const torch::Tensor& grid, const torch::Tensor& mask) const;
    // The profile and (with_tone and chirp_bins > 0; else undefined) the tone/chirp fit of one
    // grid, normalised once for both.
    // `columns`: a compact grid's subcarriers given with the call (undefined: set_compact_columns()'s).
    std::pair<torch::Tensor, torch::Tensor>
    inputs(const torch::Tensor& grid, const torch::Tensor& mask, bool with_tone, const torch::Tensor& columns = {}) const;
    // A convolution's output without autograd: a small one as one product with its dense
    // circulant matrix (cached per weight version), a large one through conv1d.
    struct dense_conv {
        std::mutex lock;
        torch::Tensor matrix, bias; // (C_in K) x (C_out K) and C_out K, (channel, bin) order
        std::vector<int64_t> versions; // of the weights it was built from
        const void* data = nullptr;
    };
    // with_bn: the BatchNorm first (folded into the dense matrix when there is one).
    torch::Tensor inference_conv(torch::nn::Conv1d conv, dense_conv& cache, const torch::Tensor& x, bool with_bn) const;

    int d_n, d_m, d_np;
    classifier_settings d_s;
    torch::Tensor d_cos, d_sin; // K x N DFT matrix (fixed, not a parameter)
    torch::Tensor d_dft;        // [[cos, sin], [-sin, cos]], 2K x 2N: the real form of the complex DFT
    torch::Tensor d_rcos, d_rsin; // M x L range-gate DFT (range_bins > 0, M < 128; larger frames: an FFT)
    torch::Tensor d_compact_cols; // set_compact_columns()
    torch::Tensor d_chirp_phase;  // tone fit: π α_j (n - (N-1)/2)², J x N
    torch::Tensor d_symbol_index; // tone fit: n = 0..N-1, 1 x 1 x N
    torch::nn::BatchNorm1d d_bn{ nullptr }, d_tone_bn{ nullptr };
    torch::nn::Conv1d d_conv1{ nullptr }, d_conv2{ nullptr };
    torch::nn::Linear d_fc1{ nullptr }, d_fc2{ nullptr }, d_out{ nullptr }, d_tone_fc{ nullptr };
    mutable dense_conv d_dense1, d_dense2;
    std::shared_ptr<template_bank_module> d_templates;
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_SPECTRAL_CLASSIFIER_DECODER_H */
