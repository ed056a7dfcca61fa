// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the trainer's process group (internal): c10d's ProcessGroupGloo behind a
 * small interface, so the trainer calls a few collectives and never sees Gloo.
 *
 * World size 1 creates nothing and every call is the identity (the single-process
 * trainer's arithmetic is untouched). Every collective waits at most
 * distributed_settings::timeout_s; a failure (a peer died, cannot connect, stopped
 * answering) becomes a std::runtime_error naming this rank, the operation and the
 * timeout, so the app exits non-zero instead of hanging.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_DISTRIBUTED_CONTEXT_H
#define INCLUDED_SEMS_LIB_LEARNING_DISTRIBUTED_CONTEXT_H

#include <gnuradio/sems/learning/distributed/distributed_settings.h>
#include <torch/torch.h>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace training {

class distributed_context
{
public:
    //! Joins the process group (rendezvous within the timeout); world size 1: nothing.
    explicit distributed_context(const distributed_settings& s);
    ~distributed_context();
    distributed_context(const distributed_context&) = delete;
    distributed_context& operator=(const distributed_context&) = delete;

    int rank() const { return d_s.rank; }
    int world_size() const { return d_s.world_size; }
    bool active() const { return d_s.world_size > 1; }
    //! The seed of this rank's own draws (data, noise, Gumbel): `seed` itself on rank 0.
    uint64_t rank_seed(uint64_t seed) const;
    //! This rank's share of `total` items (the first total % world ranks get one more).
    int64_t share(int64_t total) const;

    //! Rank 0's parameters and buffers overwrite every rank's (identical start).
    void broadcast_module(torch::nn::Module& m);
    //! Gradients of the optimizer's parameters: one flat bucket, summed over the ranks
    //! and divided by the world size; the floating-point buffers of `modules` (batch-norm
    //! running statistics) are averaged in the same bucket. Call after backward(), before
    //! step(). A gradient undefined on every rank stays undefined.
    void all_reduce_gradients(const torch::optim::Optimizer& opt,
                              const std::vector<std::shared_ptr<torch::nn::Module>>& modules);
    //! all_reduce_gradients() in two halves, so the caller can work while the gradients
    //! travel (and while a slower rank catches up): start copies the gradients into the
    //! bucket and starts the exchange; finish waits for it and writes the means back. At
    //! most one is in flight; nothing may touch the gradients or buffers in between.
    void start_gradient_all_reduce(const torch::optim::Optimizer& opt,
                                   const std::vector<std::shared_ptr<torch::nn::Module>>& modules);
    void finish_gradient_all_reduce();
    //! Element-wise sums over the ranks (float64: metric sums and counts).
    std::vector<double> all_reduce_sum(std::vector<double> v);
    //! Element-wise min / max over the ranks.
    std::vector<double> all_reduce_min(std::vector<double> v);
    std::vector<double> all_reduce_max(std::vector<double> v);
    //! The ranks' 1-D tensors (any lengths) concatenated in rank order, on every rank.
    torch::Tensor all_gather(const torch::Tensor& t);
    //! Throws if the ranks' parameters differ (they must stay bit-identical).
    void check_in_sync(const std::vector<std::shared_ptr<torch::nn::Module>>& modules, const std::string& what);

    //! Time the trainer spent in the gradient all-reduce (flatten and start, then waiting and
    //! unflattening: the part the overlapped work did not hide) and its calls.
    double gradient_seconds() const { return d_grad_seconds; }
    int64_t gradient_calls() const { return d_grad_calls; }
    int64_t gradient_floats() const { return d_grad_floats; }

    struct impl; //!< the process group (opaque: Gloo stays out of the trainer)

private:
    distributed_settings d_s;
    std::unique_ptr<impl> d_impl;
    double d_grad_seconds = 0.0;
    int64_t d_grad_calls = 0, d_grad_floats = 0;
};

} // namespace training
} // namespace sems
} // namespace gr

#endif
