// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier's template bank (classifier_settings::template_frames).
 *
 * T noiseless training frames on the final mask, each as its N_p pilots t (unit norm), sorted
 * by class. A frame y is matched against every template by its normalised correlation
 *
 *     ρ_t = |yᴴ t|² / ‖y‖²   in [0, 1],
 *
 * and each class c scores the log of the mean of exp(β ρ_t) over its templates T_c:
 *
 *     s_c = log( (1/|T_c|) Σ_{t ∈ T_c} exp(β ρ_t) ),    β = N_p / (1 - max_t ρ_t).
 *
 * Why: for y = g t + n with an unknown complex gain g and white noise of variance σ², the
 * likelihood of template t, with g at its best, is exp(‖y‖² ρ_t / σ²) up to a common factor,
 * with β = ‖y‖²/σ², so s_c is the log-likelihood of class c under the prior the training
 * frames sample: the Monte-Carlo Bayes classifier of those frames
 * (docs/results/notes/bayes_classifier.md). The frame's own best match estimates β: the noise,
 * N_p σ² of ‖y‖², is about the share 1 - max ρ that no template explains, so no SNR is given. The scores, normalised over the classes
 * (s_c - log Σ_c' exp s_c', floored at -30), and log(1 - max ρ + 1e-4) go through one layer that
 * joins the network's logits; it starts at zero, so a bank changes nothing until it has
 * trained. Unlike the network, the bank keeps every training frame's fine structure (the
 * phases of a gait or a blade passage), which is what the Monte-Carlo classifier gains by.
 *
 * The bank is empty until set() fills it (the trainer does, once the mask is final); while
 * it is empty, forward() adds nothing. Leave-one-out in training: exclude() names the bank
 * row of each frame of the next batch, whose own template would otherwise match it exactly.
 * Cost per frame: one product of the 2 N_p observations with the 2 N_p x 2 T bank
 * (8 N_p T multiply-adds), then T exponentials.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TEMPLATE_BANK_H
#define INCLUDED_SEMS_LIB_LEARNING_TEMPLATE_BANK_H

#include <gnuradio/sems/learning/api.h>
#include <torch/torch.h>
#include <mutex>

namespace gr {
namespace sems {
namespace nn {

class SEMS_LEARNING_API template_bank_module : public torch::nn::Module
{
public:
    /*!
     * \param n_pilots N_p, the pilots of each template (and of every frame matched).
     * \param n_templates T, the bank's size (>= 1).
     * \param n_classes C (>= 2).
     */
    template_bank_module(int n_pilots, int n_templates, int n_classes);

    /*!
     * \brief Fills the bank.
     * \param pilots T x 2 x N_p (real, imaginary; the mask's order), noiseless.
     * \param labels T class indices in [0, C).
     * \return for each row of `pilots` its row in the bank (sorted by class), T longs.
     * \throws std::invalid_argument for a shape or label that does not fit.
     */
    torch::Tensor set(const torch::Tensor& pilots, const torch::Tensor& labels);
    //! Whether set() (or a loaded decoder.pt) has filled the bank.
    bool ready() const;
    /*!
     * \brief The bank rows the next training forward() leaves out, one per frame (-1: none);
     * undefined: none. Read only in training mode.
     */
    void exclude(const torch::Tensor& rows) { d_exclude = rows; }
    /*!
     * \brief The class scores and the best match of each frame (no gradient).
     * \param obs B x 2 x N_p pilot observations (the mask's order).
     * \return B x (C + 1): the normalised class scores s_c, then log(1 - max ρ + 1e-4).
     */
    torch::Tensor scores(const torch::Tensor& obs) const;
    //! B x C logits to add to the network's: the joining layer over scores(obs).
    torch::Tensor forward(const torch::Tensor& obs);

private:
    int d_np, d_t, d_c;
    // The 2 N_p x 2 T matrix whose product with [y_re, y_im] is [Re(yᴴt), Im(yᴴt)], built from
    // d_templates when first needed (decoder.pt keeps the templates once, not this).
    torch::Tensor matrix() const;
    struct matrix_cache {
        std::mutex lock;
        torch::Tensor value;
        int64_t version = -1;
        const void* data = nullptr;
    };
    torch::Tensor d_templates; // T x 2 x N_p unit-norm templates, sorted by class
    mutable matrix_cache d_matrix;
    torch::Tensor d_class_end; // C longs: the bank's rows of class c are [end[c-1], end[c])
    torch::Tensor d_exclude;
    torch::nn::Linear d_out{ nullptr };
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_TEMPLATE_BANK_H */
