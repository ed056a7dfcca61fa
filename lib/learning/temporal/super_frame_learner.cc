// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: learning the pilots of a super-frame (see super_frame_learner.h). */
#include "learning/temporal/super_frame_learner.h"
#include "learning/temporal/track_data.h"
#include "learning/training/semantic_encoder.h"
#include "learning/training/trainer_data.h"
#include <ATen/CPUGeneratorImpl.h>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace sems {
namespace temporal {

// Named, not anonymous: the unity build puts this file beside others with helpers of their own.
namespace super_frame_detail {
using clock_type = std::chrono::steady_clock;

// The learner's view of a window of tracks: noisy grids, labels, frames inside each track and
// each frame's set.
struct windows {
    torch::Tensor h;     // T x W x 2 x N x M, noiseless
    torch::Tensor label; // T
    torch::Tensor valid; // T x W (bool)
    torch::Tensor set;   // T x W (long): (track + t) mod F
};

windows draw_windows(const model_bundle& frame, const scene& sc, uint64_t seed, int64_t first, int64_t count, int w, int f)
{
    const auto t = draw_track_grids(frame.frame, sc, seed, first, count, w, frame.class_names);
    windows out;
    out.h = t.obs;
    out.label = t.label;
    out.valid = torch::arange(w, torch::kLong).view({ 1, w }) < t.length.view({ count, 1 });
    out.set = (torch::arange(first, first + count, torch::kLong).view({ count, 1 }) +
               torch::arange(w, torch::kLong).view({ 1, w })) %
              f;
    return out;
}

// h + CN(0, σ²) with one SNR per track, uniform in [lo, hi] dB.
torch::Tensor noisy(const torch::Tensor& h, double lo, double hi, at::Generator gen)
{
    const int64_t count = h.size(0), w = h.size(1);
    auto var = training::draw_noise_variance(count, lo, hi, gen).view({ count, 1 }).expand({ count, w }).reshape({ -1 });
    auto flat = h.reshape({ count * w, h.size(2), h.size(3), h.size(4) });
    return training::add_noise(flat, var, gen).view(h.sizes());
}

// The frames' log-probabilities (T x W x C) with the masks of their sets: the frames of
// each set in one pass of the decoder, at that set's mask.
torch::Tensor frame_log_probs(const nn::task_decoder& dec,
                              const torch::Tensor& y,
                              const torch::Tensor& set,
                              const std::vector<torch::Tensor>& masks,
                              int64_t c)
{
    const int64_t t = y.size(0), w = y.size(1);
    auto flat = y.reshape({ t * w, y.size(2), y.size(3), y.size(4) });
    auto sets = set.reshape({ -1 });
    auto logp = torch::zeros({ t * w, c }, torch::kFloat);
    for (size_t f = 0; f < masks.size(); ++f) {
        auto rows = (sets == static_cast<int64_t>(f)).nonzero().flatten();
        if (rows.size(0) == 0)
            continue;
        auto out = dec->forward(flat.index_select(0, rows) * masks[f], masks[f]);
        logp = logp.index_copy(0, rows, torch::log_softmax(out.logits, -1));
    }
    return logp.view({ t, w, c });
}

// The fused decision's accuracy after every frame of every window (frames inside tracks).
double fused_accuracy(const torch::Tensor& logp, const torch::Tensor& label, const torch::Tensor& valid)
{
    auto pred = logp.cumsum(1).argmax(-1);
    auto ok = (pred == label.view({ -1, 1 })) & valid;
    return ok.sum().item<double>() / std::max<double>(1.0, valid.sum().item<double>());
}

// A set's scores at `mask`: β on the symbols and subcarriers it uses, so that its N_p best
// elements are the mask's own when the mask is a product of symbols and subcarriers (as a
// learned gumbel_topk mask of a[n] + b[m] is), and Gumbel draws around it explore from there.
void start_at(nn::semantic_encoder& enc, const pilot_mask& mask)
{
    constexpr double beta = 3.0;
    torch::NoGradGuard ng;
    for (auto& p : enc->named_parameters()) {
        if (p.key() == "symbol_scores")
            for (const auto& q : mask.positions())
                p.value()[q.n] = beta;
        if (p.key() == "subcarrier_scores")
            for (const auto& q : mask.positions())
                p.value()[q.m] = beta;
    }
}

std::vector<torch::Tensor> snapshot(const std::shared_ptr<torch::nn::Module>& m)
{
    std::vector<torch::Tensor> out;
    for (const auto& p : m->parameters())
        out.push_back(p.detach().clone());
    for (const auto& b : m->buffers())
        out.push_back(b.detach().clone());
    return out;
}

void restore(const std::shared_ptr<torch::nn::Module>& m, const std::vector<torch::Tensor>& state)
{
    torch::NoGradGuard ng;
    size_t i = 0;
    for (auto& p : m->parameters())
        p.copy_(state[i++]);
    for (auto& b : m->buffers())
        b.copy_(state[i++]);
}
} // namespace super_frame_detail
using namespace super_frame_detail;

super_frame_result learn_super_frame(const model_bundle& frame,
                                     const scene& sc,
                                     const track_training_settings& s,
                                     int64_t first_val_track,
                                     int64_t val_tracks,
                                     const std::function<void(const std::string&)>& say)
{
    const int f = s.super_frames;
    const int n = frame.frame.n_symbols, m = frame.frame.n_subcarriers, np = frame.mask.size();
    const int w = std::min(2 * f, s.track_frames);
    const int64_t c = static_cast<int64_t>(frame.class_names.size());
    const auto t0 = clock_type::now();
    const auto train = draw_windows(frame, sc, s.seed, 0, s.mask_tracks, w, f);
    const auto val = draw_windows(frame, sc, s.seed, first_val_track, val_tracks, w, f);
    {
        std::ostringstream os;
        os << "super-frame of " << f << " sets of " << np << " pilots: " << s.mask_tracks << " training and " << val_tracks
           << " validation tracks of " << w << " frames (" << std::setprecision(3)
           << (train.h.numel() + val.h.numel()) * 4.0 / (1 << 20) << " MiB of grids, "
           << std::chrono::duration<double>(clock_type::now() - t0).count() << " s to draw)";
        say(os.str());
    }

    // The frame decoder, trained on from the frame bundle's weights.
    auto dec = nn::make_decoder(frame.decoder, n, m, np, frame.directory + "/" + model_bundle::bundle_file);
    nn::load_module(dec, frame.weights_path());
    std::vector<nn::semantic_encoder> enc;
    std::vector<torch::optim::OptimizerParamGroup> groups;
    groups.emplace_back(dec->parameters(), std::make_unique<torch::optim::AdamOptions>(s.mask_lr));
    for (int i = 0; i < f; ++i) {
        enc.emplace_back(np, n, m, nn::encoder_settings{}, false, frame.frame.guard_subcarriers);
        if (s.mask_start == "frame")
            start_at(enc.back(), frame.mask);
        groups.emplace_back(enc.back()->parameters(),
                            std::make_unique<torch::optim::AdamOptions>(s.mask_encoder_lr));
    }
    torch::optim::Adam opt(groups, torch::optim::AdamOptions(s.mask_lr));
    auto gen = at::detail::createCPUGenerator(s.seed ^ 0x7375706572667261ULL);
    const auto val_y = noisy(val.h, s.snr_min_db, s.snr_max_db, gen);

    auto final_masks = [&]() {
        std::vector<torch::Tensor> grids;
        std::vector<pilot_mask> sets;
        for (auto& e : enc) {
            const auto idx = e->final_indices();
            auto g = torch::zeros({ static_cast<int64_t>(n) * m });
            std::vector<pilot_position> pos;
            for (auto i : idx) {
                g[i] = 1.0f;
                pos.push_back({ static_cast<int>(i / m), static_cast<int>(i % m) });
            }
            grids.push_back(g.view({ n, m }));
            sets.emplace_back(n, m, pos, frame.mask.pilot_symbol(), nlohmann::json{ { "kind", "learned" } });
        }
        return std::make_pair(grids, sets);
    };

    super_frame_result r{ super_frame_mask(frame.mask), dec, nlohmann::json::array() };
    const nn::encoder_settings es;
    double tau = es.temperature_start; // annealed per epoch down to its floor, as the frame trainer's
    double best = -1.0;
    int since_best = 0;
    std::vector<pilot_mask> best_sets;
    auto best_state = snapshot(dec);
    auto evaluate = [&](const std::vector<torch::Tensor>& grids) {
        torch::NoGradGuard ng;
        dec->eval();
        return fused_accuracy(frame_log_probs(dec, val_y, val.set, grids, c), val.label, val.valid);
    };
    // Epoch 0 of a start at the frame mask: every set at the frame bundle's mask, the repeated
    // mask the learner starts from, kept unless an epoch validates better. A random start has
    // no such candidate (its first sets are random draws).
    if (s.mask_start == "frame") {
        auto [grids, sets] = final_masks();
        best = evaluate(grids);
        best_sets = sets;
        std::ostringstream os;
        os << "super-frame epoch 0: every set at the frame bundle's mask, validation accuracy of the fusion over the "
              "window " << std::setprecision(4) << best;
        say(os.str());
        r.history.push_back({ { "epoch", 0 }, { "val_fused_accuracy", best } });
    }
    for (int epoch = 1; epoch <= s.mask_epochs; ++epoch) {
        const auto te = clock_type::now();
        const auto y = noisy(train.h, s.snr_min_db, s.snr_max_db, gen);
        dec->train();
        auto order = torch::randperm(s.mask_tracks, gen, torch::kLong);
        double loss_sum = 0.0;
        int64_t steps = 0;
        for (int64_t a = 0; a < s.mask_tracks; a += s.batch) {
            auto idx = order.slice(0, a, std::min<int64_t>(s.mask_tracks, a + s.batch));
            std::vector<torch::Tensor> masks;
            for (auto& e : enc)
                masks.push_back(e->sample_mask(tau, true));
            const auto logp = frame_log_probs(dec, y.index_select(0, idx), train.set.index_select(0, idx), masks, c);
            auto v = train.valid.index_select(0, idx).flatten().nonzero().flatten();
            auto lbl = train.label.index_select(0, idx).view({ -1, 1 }).expand({ idx.size(0), w }).flatten().index_select(0, v);
            namespace F = torch::nn::functional;
            // log_softmax of the summed log-probabilities is the fused posterior's log.
            auto fused = logp.cumsum(1).reshape({ -1, c }).index_select(0, v);
            auto loss = F::cross_entropy(fused, lbl) + F::nll_loss(logp.reshape({ -1, c }).index_select(0, v), lbl);
            opt.zero_grad();
            loss.backward();
            opt.step();
            loss_sum += loss.item<double>();
            ++steps;
        }
        // Validation on the final sets (the N_p best scores of each).
        auto [grids, sets] = final_masks();
        const double acc = evaluate(grids);
        int distinct = 0; // pilots of a set no other set has
        for (size_t i = 0; i < grids.size(); ++i) {
            auto others = torch::zeros_like(grids[i]);
            for (size_t j = 0; j < grids.size(); ++j)
                if (j != i)
                    others = others + grids[j];
            distinct += ((grids[i] > 0) & (others == 0)).sum().item<int>();
        }
        const double secs = std::chrono::duration<double>(clock_type::now() - te).count();
        std::ostringstream os;
        os << "super-frame epoch " << epoch << "/" << s.mask_epochs << ": loss " << std::setprecision(4)
           << loss_sum / std::max<int64_t>(1, steps) << ", validation accuracy of the fusion over the window " << acc
           << ", pilots in one set only " << distinct << "/" << f * np << ", temperature " << std::setprecision(3)
           << tau << " (" << secs << " s)";
        say(os.str());
        r.history.push_back({ { "epoch", epoch },
                              { "loss", loss_sum / std::max<int64_t>(1, steps) },
                              { "val_fused_accuracy", acc },
                              { "pilots_in_one_set_only", distinct },
                              { "temperature", tau },
                              { "seconds", secs } });
        tau = std::max(es.temperature_floor, tau * es.temperature_decay);
        if (acc > best) {
            best = acc;
            since_best = 0;
            best_sets = sets;
            best_state = snapshot(dec);
        } else if (++since_best >= s.patience) {
            say("super-frame: early stop, no better validation for " + std::to_string(s.patience) + " epochs");
            break;
        }
    }
    restore(dec, best_state);
    dec->eval();
    r.masks = super_frame_mask(best_sets,
                               { { "kind", "learned_super_frame" },
                                 { "sets", f },
                                 { "objective", "fused cross-entropy over frames, jointly with the frame decoder" } },
                               "learned super-frame");
    r.decoder = dec;
    return r;
}

} // namespace temporal
} // namespace sems
} // namespace gr
