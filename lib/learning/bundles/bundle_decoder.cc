// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: inference on a model bundle (LibTorch behind the pimpl of bundle_decoder.h). */
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include "learning/networks/delay_decoder.h"
#include "learning/memory/malloc_tuning.h"
#include "learning/networks/spectral_classifier_decoder.h"
#include "learning/networks/task_decoder.h"
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

struct bundle_decoder::impl {
    model_bundle bundle;
    nn::task_decoder net;
    std::vector<int64_t> indices;
    torch::Tensor index; // the same as a kLong tensor, built once
    int threads = 0; // intra-op threads of this decoder's inference; 0 = LibTorch's own

    // LibTorch's intra-op thread count is per calling thread with its OpenMP backend
    // (at::set_num_threads -> omp_set_num_threads, an ICV of the calling thread), so it
    // is set where inference runs: each sink's work thread keeps its own count, instead
    // of the last decoder constructed setting it for everyone.
    void use_threads() const
    {
        if (threads > 0 && at::get_num_threads() != threads)
            at::set_num_threads(threads);
    }
    torch::Tensor mask; // N x M, 1 at the pilots (N x M' for a compact grid, see below)
    // The spectral classifier reads only the subcarriers that carry pilots: its input grid
    // is built with those M' columns alone (no dense N x M grid per frame). With a super-frame
    // the columns are those any set occupies, and each set has its own index and mask.
    int grid_columns = 0; // M, or M' for the spectral classifier
    // A super-frame: per set f, its grid as `index`, `mask` and `grid_columns` are for one mask
    // (for the spectral classifier the set's own occupied subcarriers, `set_cols`, given with
    // each call), so a frame of set f is decoded exactly as by a bundle whose mask is set f.
    std::vector<torch::Tensor> set_index, set_mask, set_cols;
    std::vector<int> set_columns;
    std::shared_ptr<nn::spectral_classifier_decoder_module> spectral; // net, when it is one (cast once)

    int n_sets() const { return set_index.empty() ? 1 : static_cast<int>(set_index.size()); }

    torch::Tensor grid(const gr_complex* obs, int batch, const torch::Tensor& idx, int columns) const
    {
        if (batch < 0)
            throw std::invalid_argument("bundle_decoder: batch must be >= 0");
        const int np = bundle.mask.size();
        // gr_complex is two packed floats: view the caller's buffer as batch x N_p x 2.
        auto o = torch::from_blob(const_cast<gr_complex*>(obs), { batch, np, 2 }, torch::kFloat);
        return nn::scatter_pilots(o, idx, bundle.frame.n_symbols, columns);
    }

    // The rule of bundle_decoder.h: a batch with a NaN or Inf anywhere is refused, naming
    // the first such frame (a network would answer it with NaN, or worse, a number).
    void check_finite(const gr_complex* obs, int batch, const char* what) const
    {
        const size_t np = static_cast<size_t>(bundle.mask.size());
        for (int b = 0; b < batch; ++b) {
            const gr_complex* frame = obs + static_cast<size_t>(b) * np;
            for (size_t k = 0; k < np; ++k)
                if (!std::isfinite(frame[k].real()) || !std::isfinite(frame[k].imag()))
                    throw std::invalid_argument(
                        std::string("bundle_decoder::") + what + ": frame " + std::to_string(b) + " of the batch of " +
                        std::to_string(batch) + " holds a non-finite observation (pilot " + std::to_string(k) +
                        "): frames with NaN or Inf are not decoded; leave them out of the batch");
        }
    }

    // The set of every frame of a batch: all 0 for one frame's mask (`sets` may then be
    // null); a super-frame needs them, each in [0, F).
    void check_sets(const int* sets, int batch, const char* what) const
    {
        const int f = n_sets();
        if (!sets) {
            if (f > 1)
                throw std::invalid_argument(std::string("bundle_decoder::") + what + ": bundle " + bundle.directory +
                                            " has a mask spanning a super-frame of " + std::to_string(f) +
                                            " frames: give the set of each frame (its frame index mod " +
                                            std::to_string(f) + ")");
            return;
        }
        for (int b = 0; b < batch; ++b)
            if (sets[b] < 0 || sets[b] >= f)
                throw std::invalid_argument(std::string("bundle_decoder::") + what + ": frame " + std::to_string(b) +
                                            " of the batch names set " + std::to_string(sets[b]) + ", but bundle " +
                                            bundle.directory + "'s mask has " + std::to_string(f) + " set(s)");
    }

    nn::decoder_output run(const gr_complex* obs, int batch, task_kind need, const char* what, const int* sets) const
    {
        if (bundle.task != need)
            throw std::invalid_argument(std::string("bundle_decoder::") + what + ": bundle " + bundle.directory +
                                        " is a \"" + task_name(bundle.task) + "\" model");
        check_finite(obs, batch, what);
        check_sets(sets, batch, what);
        use_threads();
        // Inference mode: no autograd bookkeeping at all (no version counters or view
        // tracking), cheaper per op than NoGradGuard; the outputs are copied out below.
        c10::InferenceMode im;
        if (n_sets() == 1)
            return net->forward(grid(obs, batch, index, grid_columns), mask);
        // A super-frame: the frames of each set in one pass with that set's mask, the
        // answers put back in the batch's order.
        const size_t np = static_cast<size_t>(bundle.mask.size());
        nn::decoder_output all;
        auto put = [&](torch::Tensor& dst, const torch::Tensor& part, const torch::Tensor& rows) {
            if (!part.defined())
                return;
            if (!dst.defined()) {
                auto shape = part.sizes().vec();
                shape[0] = batch;
                dst = torch::empty(shape, part.options());
            }
            dst.index_copy_(0, rows, part);
        };
        std::vector<gr_complex> picked;
        for (int f = 0; f < n_sets(); ++f) {
            std::vector<int64_t> rows;
            for (int b = 0; b < batch; ++b)
                if (sets[b] == f)
                    rows.push_back(b);
            if (rows.empty())
                continue;
            picked.resize(rows.size() * np);
            for (size_t r = 0; r < rows.size(); ++r)
                std::copy(obs + rows[r] * np, obs + (rows[r] + 1) * np, picked.begin() + r * np);
            const auto g = grid(picked.data(), static_cast<int>(rows.size()), set_index[f], set_columns[f]);
            auto out = spectral ? spectral->forward(g, set_mask[f], set_cols[f]) : net->forward(g, set_mask[f]);
            const auto at = torch::tensor(rows, torch::kLong);
            put(all.logits, out.logits, at);
            put(all.features, out.features, at);
            put(all.profile, out.profile, at);
        }
        return all;
    }
};

bundle_decoder::bundle_decoder(const model_bundle& bundle, int threads) : d_impl(std::make_unique<impl>())
{
    tune_malloc_for_tensors(); // decoding allocates and frees every intermediate tensor
    d_impl->threads = threads;
    d_impl->use_threads(); // the constructing thread too (single-threaded callers)
    d_impl->bundle = bundle;
    const std::string source = bundle.directory + "/" + model_bundle::bundle_file;
    d_impl->net = nn::make_decoder(bundle.decoder, bundle.frame.n_symbols, bundle.frame.n_subcarriers,
                                   bundle.mask.size(), source);
    nn::load_module(d_impl->net, bundle.weights_path()); // the weights file bundle.json names
    d_impl->net->eval();
    d_impl->spectral = std::dynamic_pointer_cast<nn::spectral_classifier_decoder_module>(d_impl->net);
    const int n = bundle.frame.n_symbols, msub = bundle.frame.n_subcarriers;
    const int n_sets = bundle.super_frames();
    if (n_sets > 1 && bundle.task != task_kind::classify)
        throw std::invalid_argument(source + ": a mask spanning a super-frame of " + std::to_string(n_sets) +
                                    " frames is for classifiers; a \"" + task_name(bundle.task) + "\" bundle has one frame's mask");
    if (n_sets > 1 && bundle.decoder.value("settings", nlohmann::json::object()).value("template_frames", 0) > 0)
        throw std::invalid_argument(source + ": a template bank holds one mask's pilots; a mask spanning a super-frame "
                                             "of " + std::to_string(n_sets) + " frames needs a decoder without one");
    const bool spectral = bundle.decoder.value("kind", std::string()) == "classifier_spectral";
    // One mask's grid: all M columns, or for the spectral classifier only the occupied
    // subcarriers (in increasing order; a pilot at flat n*M + m goes to n*M' + column(m)).
    struct set_grid {
        torch::Tensor index, mask;
        std::vector<int64_t> occupied; // the subcarrier of each compact column (the range gate's phases)
        int columns = 0;
    };
    auto grid_of = [&](const pilot_mask& pm) {
        set_grid out;
        std::vector<int64_t> idx;
        for (int i : pm.flat_indices())
            idx.push_back(i);
        out.columns = msub;
        if (spectral) {
            std::vector<int> column(msub, -1);
            for (int64_t i : idx)
                column[i % msub] = 0;
            int next = 0;
            for (auto& c : column)
                if (c == 0)
                    c = next++;
            out.columns = next;
            for (auto& i : idx)
                i = (i / msub) * next + column[i % msub];
            for (int m = 0; m < msub; ++m)
                if (column[m] >= 0)
                    out.occupied.push_back(m);
        }
        out.index = torch::tensor(idx, torch::kLong);
        auto m = torch::zeros({ static_cast<int64_t>(n) * out.columns });
        m.index_fill_(0, out.index, 1.0f);
        out.mask = m.view({ n, out.columns });
        return out;
    };
    for (int i : bundle.mask.flat_indices())
        d_impl->indices.push_back(i);
    const auto first = grid_of(bundle.mask);
    d_impl->index = first.index;
    d_impl->mask = first.mask;
    d_impl->grid_columns = first.columns;
    if (spectral)
        if (auto sc = std::dynamic_pointer_cast<nn::spectral_classifier_decoder_module>(d_impl->net))
            sc->set_compact_columns(first.occupied);
    if (n_sets > 1)
        for (int f = 0; f < n_sets; ++f) {
            const auto g = grid_of(bundle.mask_of_set(f));
            d_impl->set_index.push_back(g.index);
            d_impl->set_mask.push_back(g.mask);
            d_impl->set_columns.push_back(g.columns);
            d_impl->set_cols.push_back(torch::tensor(g.occupied, torch::kLong));
        }
    // The delay decoder's refinement stage fits the pilots where the mask put them.
    if (auto dd = std::dynamic_pointer_cast<nn::delay_decoder_module>(d_impl->net))
        dd->set_pilot_positions(bundle.frame, d_impl->indices);
}

bundle_decoder::~bundle_decoder() = default;

const model_bundle& bundle_decoder::bundle() const { return d_impl->bundle; }
int bundle_decoder::n_pilots() const { return d_impl->bundle.mask.size(); }
int bundle_decoder::super_frames() const { return d_impl->n_sets(); }

std::vector<float> bundle_decoder::classify(const gr_complex* obs, int batch, const int* sets) const
{
    if (batch == 0)
        return {};
    auto out = d_impl->run(obs, batch, task_kind::classify, "classify", sets);
    auto p = torch::softmax(out.logits, -1).contiguous();
    return std::vector<float>(p.data_ptr<float>(), p.data_ptr<float>() + p.numel());
}

std::vector<double> bundle_decoder::estimate_delay_index(const gr_complex* obs, int batch) const
{
    if (batch == 0)
        return {};
    auto out = d_impl->run(obs, batch, task_kind::delay, "estimate_delay", nullptr);
    auto d = out.delay_index.to(torch::kDouble).contiguous();
    return std::vector<double>(d.data_ptr<double>(), d.data_ptr<double>() + d.numel());
}

std::vector<double> bundle_decoder::estimate_delay(const gr_complex* obs, int batch) const
{
    auto d = estimate_delay_index(obs, batch);
    for (auto& x : d)
        x /= d_impl->bundle.frame.bandwidth_hz; // index = τ·B
    return d;
}

std::vector<float> bundle_decoder::features(const gr_complex* obs, int batch, const int* sets) const
{
    if (batch == 0)
        return {};
    auto out = d_impl->run(obs, batch, task_kind::classify, "features", sets);
    auto f = out.features.contiguous();
    return std::vector<float>(f.data_ptr<float>(), f.data_ptr<float>() + f.numel());
}

namespace {
std::shared_ptr<nn::spectral_classifier_decoder_module> profile_decoder(const nn::task_decoder& net,
                                                                        const model_bundle& b)
{
    auto sc = std::dynamic_pointer_cast<nn::spectral_classifier_decoder_module>(net);
    if (!sc)
        throw std::invalid_argument("bundle_decoder::evidence: bundle " + b.directory + " has a \"" +
                                    b.decoder.value("kind", std::string()) +
                                    "\" decoder, which has no Doppler profile (classifier_spectral has)");
    return sc;
}
} // namespace

std::vector<float>
bundle_decoder::evidence(const gr_complex* obs, int batch, bool doppler_profile, const int* sets) const
{
    if (batch == 0)
        return {};
    auto out = d_impl->run(obs, batch, task_kind::classify, "evidence", sets);
    std::vector<torch::Tensor> parts{ out.features };
    if (doppler_profile) {
        profile_decoder(d_impl->net, d_impl->bundle); // refuses a decoder without one
        parts.push_back(out.profile.flatten(1));      // the profile the forward pass computed
    }
    parts.push_back(torch::log_softmax(out.logits, -1));
    auto e = torch::cat(parts, 1).contiguous();
    return std::vector<float>(e.data_ptr<float>(), e.data_ptr<float>() + e.numel());
}

int bundle_decoder::evidence_size(bool doppler_profile) const
{
    if (d_impl->bundle.task != task_kind::classify)
        return 0;
    int n = feature_size() + static_cast<int>(d_impl->bundle.class_names.size());
    if (doppler_profile) {
        const auto& s = profile_decoder(d_impl->net, d_impl->bundle)->settings();
        n += s.doppler_bins * (s.mti == "both" ? 2 : 1);
    }
    return n;
}

int bundle_decoder::feature_size() const
{
    if (d_impl->bundle.task != task_kind::classify)
        return 0;
    return d_impl->bundle.decoder.at("settings").value("features", 16);
}

} // namespace sems
} // namespace gr
