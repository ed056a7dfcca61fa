// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: inference on a model bundle, shared by the sinks, the evaluation app and
 * the bindings. Rebuilds the decoder network from bundle.json, loads its weights and
 * maps pilot observations (Y/s_p at the mask positions, in mask order) to answers.
 * LibTorch stays behind this header (pimpl), so blocks and bindings need no torch headers.
 */
#ifndef INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H
#define INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/model_bundle.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

class SEMS_LEARNING_API bundle_decoder
{
public:
    // threads <= 0 leaves LibTorch's intra-op thread count alone; threads > 0 is applied in
    // the thread that runs each inference (LibTorch's OpenMP count is per thread), so two
    // decoders (two sinks) in one process each keep the count they were given.
    explicit bundle_decoder(const model_bundle& bundle, int threads = 1);
    ~bundle_decoder();

    const model_bundle& bundle() const;
    int n_pilots() const;

    // obs: batch x N_p, row-major. Returns batch x C class probabilities, row-major.
    std::vector<float> classify(const gr_complex* obs, int batch) const;
    // obs: batch x N_p. Returns the delay of the target of interest, in seconds.
    std::vector<double> estimate_delay(const gr_complex* obs, int batch) const;
    // obs: batch x N_p. The same estimate as a delay index (τ·B).
    std::vector<double> estimate_delay_index(const gr_complex* obs, int batch) const;
    // obs: batch x N_p. Classifier only: batch x feature_size() embeddings (for t-SNE).
    std::vector<float> features(const gr_complex* obs, int batch) const;
    int feature_size() const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H */
