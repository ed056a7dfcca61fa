// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: joint pilot/decoder training (see include/gnuradio/sems/learning/training/trainer.h). */
#include "learning/training/trainer_data.h"
#include "learning/networks/classifier_decoder.h"
#include "learning/networks/delay_decoder.h"
#include "learning/distributed/distributed_context.h"
#include "learning/memory/malloc_tuning.h"
#include "learning/training/mask_settle_rule.h"
#include "learning/networks/reconstruction_decoder.h"
#include "learning/training/semantic_encoder.h"
#include "learning/networks/spectral_classifier_decoder.h"
#include <gnuradio/sems/learning/training/trainer.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace sems {

using nlohmann::json;
namespace {

using clock_type = std::chrono::steady_clock;
double since(clock_type::time_point t0)
{
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}
// CPU seconds of the process (all threads) since `c0`, a std::clock() reading.
double cpu_since(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

void fail(const std::string& what) { throw std::invalid_argument("training settings: " + what); }

scene default_scene() { return scene::random(random_spec{}); }

// How many paths the target of interest has, and how far behind its first path the
// last one can arrive (delay indices).
struct reach_of_scene {
    int paths = 1;
    double max_excess_index = 0.0;
};
reach_of_scene scene_reach(const scene& sc, const frame_settings& fs)
{
    reach_of_scene r;
    double excess_m = 0.0;
    if (const auto& rs = sc.random_settings()) {
        r.paths = rs->paths_per_target;
        if (rs->paths_per_target > 1)
            excess_m = rs->excess_range_max_m;
    } else {
        const auto& toi = sc.targets()[sc.target_of_interest()];
        r.paths = static_cast<int>(toi.paths.size());
        for (const auto& p : toi.paths)
            excess_m = std::max(excess_m, p.excess_range_m);
    }
    r.max_excess_index = fs.delay_index(fs.delay_from_range(excess_m));
    return r;
}

// Copies of a module's parameters and buffers (best-epoch checkpoint).
std::vector<torch::Tensor> snapshot(const std::shared_ptr<torch::nn::Module>& m)
{
    std::vector<torch::Tensor> out;
    for (auto& p : m->parameters())
        out.push_back(p.detach().clone());
    for (auto& b : m->buffers())
        out.push_back(b.detach().clone());
    return out;
}
void restore(const std::shared_ptr<torch::nn::Module>& m, const std::vector<torch::Tensor>& s)
{
    torch::NoGradGuard ng;
    size_t i = 0;
    for (auto& p : m->parameters())
        p.copy_(s[i++]);
    for (auto& b : m->buffers())
        b.copy_(s[i++]);
}

class trainer
{
public:
    trainer(const training_settings& s, std::ostream* log) : d_s(s), d_log(log) {}

    training_result run();

private:
    const training_settings& d_s;
    std::ostream* d_log;
    training::data_set d_data;
    std::unique_ptr<training::distributed_context> d_dist; // world size 1: identities
    int d_n = 0, d_m = 0;
    double d_spacing = 1.0;

    bool higher_is_better(bool reconstruction) const
    {
        return !reconstruction && d_s.task == task_kind::classify;
    }

    nn::task_decoder make_task_decoder(const scene& sc)
    {
        if (d_s.task == task_kind::classify) {
            auto cs = d_s.classifier;
            cs.n_classes = static_cast<int>(d_data.class_names.size());
            if (cs.template_frames == -1) // every training frame
                cs.template_frames = static_cast<int>(d_data.train.size());
            return nn::make_classifier(d_n, d_m, d_s.n_pilots, cs);
        }
        auto ds = d_s.delay;
        // Dictionary grid from the delays the data contain, with margin, at the set spacing.
        ds.tau_min_index = std::floor(d_data.delay_min - d_s.delay_margin);
        ds.tau_max_index = std::ceil(d_data.delay_max + d_s.delay_margin);
        ds.q = static_cast<int>(std::lround((ds.tau_max_index - ds.tau_min_index) / d_s.delay_spacing)) + 1;
        d_spacing = ds.spacing();
        // The first path must stay in view of the later ones: the receptive field must
        // cover twice the scene's largest excess delay (a path that far behind on either side).
        const auto reach = scene_reach(sc, d_s.frame);
        if (ds.receptive_field_index() < 2.0 * reach.max_excess_index)
            fail("the delay decoder's receptive field is " + std::to_string(ds.receptive_field_index()) +
                 " delay indices, below twice the largest excess delay of " + d_s.scene_source + " (2 x " +
                 std::to_string(reach.max_excess_index) + "): raise --depth, --kernel or --dilation-growth");
        // Refinement settings left at "from the scene" (-1).
        // L paths are 3L + 1 real unknowns (L complex gains, L delays, one Doppler) against
        // 2 N_p real observations: with no more observations than unknowns the fit
        // interpolates the noise, so "from the scene" then means no refinement (said in the log).
        if (ds.refine_paths < 0) {
            ds.refine_paths = reach.paths;
            if (2 * d_s.n_pilots <= 3 * reach.paths + 1) {
                ds.refine_paths = 0;
                if (d_log)
                    *d_log << "delay refinement off: " << reach.paths << " paths need more than "
                           << (3 * reach.paths + 1) / 2 << " pilots, the mask has " << d_s.n_pilots << "\n";
            }
        }
        if (ds.refine_span_index <= 0.0)
            ds.refine_span_index = reach.max_excess_index + 1.0;
        return std::make_shared<nn::delay_decoder_module>(d_n, d_m, d_s.n_pilots, ds);
    }

    // Task loss (or the reconstruction MSE) of one forward pass.
    torch::Tensor loss(const nn::decoder_output& out,
                       const training::split& sp,
                       const torch::Tensor& idx,
                       const torch::Tensor& h_clean,
                       double ce_weight) const
    {
        if (out.channel.defined())
            return torch::mse_loss(out.channel, h_clean);
        if (d_s.task == task_kind::classify)
            return torch::nn::functional::cross_entropy(out.logits, sp.label.index_select(0, idx));
        auto tau = sp.delay.index_select(0, idx);
        // Soft target: the truth split linearly between its two neighbouring grid points.
        const auto& grid = out.logits;
        const int64_t q = grid.size(1);
        auto pos = ((tau - d_tau_min) / d_spacing).clamp(0, q - 1);
        auto lo = pos.floor().clamp(0, q - 1);
        auto w_hi = pos - lo;
        auto hi = (lo + 1).clamp(0, q - 1);
        auto target = torch::zeros_like(grid);
        target.scatter_add_(1, lo.to(torch::kLong).unsqueeze(1), (1 - w_hi).unsqueeze(1));
        target.scatter_add_(1, hi.to(torch::kLong).unsqueeze(1), w_hi.unsqueeze(1));
        auto ce = -(target * torch::log_softmax(grid, 1)).sum(1).mean();
        // L1 in delay indices: small next to the cross-entropy until the peak is found.
        auto l1 = (out.delay_index - tau).abs().mean();
        return ce_weight * ce + l1;
    }

    // Validation/test metric on a fixed mask: accuracy, delay MAE (index) or MSE.
    struct scored {
        double metric;
        int64_t count; // frames scored over all ranks
        torch::Tensor logits, delay, obs;
    };
    // noise_grid (N x M, optional): each element's noise scale, 1/sqrt(p_k) at pilot k
    // (pilot_mask::noise_scale_of_power); undefined for equal power.
    scored evaluate(const nn::task_decoder& dec,
                    const std::vector<int64_t>& mask_idx,
                    const training::split& sp,
                    const torch::Tensor& noisy,
                    int64_t limit = 0,
                    const torch::Tensor& noise_grid = {}) const
    {
        torch::NoGradGuard ng;
        dec->eval();
        if (auto dd = std::dynamic_pointer_cast<nn::delay_decoder_module>(dec)) {
            auto sorted = mask_idx; // the refinement fits the pilots in mask order
            std::sort(sorted.begin(), sorted.end());
            dd->set_pilot_positions(d_s.frame, sorted);
        }
        const int64_t total = limit > 0 ? std::min<int64_t>(limit, sp.size()) : sp.size();
        std::vector<torch::Tensor> logits, delay, obs;
        double sum = 0.0;
        for (int64_t a = 0; a < total; a += d_s.batch) {
            const int64_t b = std::min<int64_t>(total, a + d_s.batch);
            auto y = noisy.slice(0, a, b);
            if (noise_grid.defined())
                y = scale_noise(y, sp.h.slice(0, a, b), noise_grid);
            // The inference path of bundle_decoder: gather the pilots, scatter, forward.
            auto o = nn::gather_pilots(y, mask_idx);
            auto out = dec->forward(nn::scatter_pilots(o, mask_idx, d_n, d_m), mask_grid(mask_idx));
            obs.push_back(o);
            if (out.channel.defined()) {
                sum += torch::mse_loss(out.channel, sp.h.slice(0, a, b), torch::Reduction::Sum).item<double>() /
                       (2.0 * d_n * d_m);
            } else if (d_s.task == task_kind::classify) {
                logits.push_back(out.logits);
                sum += out.logits.argmax(1).eq(sp.label.slice(0, a, b)).sum().item<double>();
            } else {
                delay.push_back(out.delay_index);
                sum += (out.delay_index - sp.delay.slice(0, a, b)).abs().sum().item<double>();
            }
        }
        dec->train();
        scored r;
        const auto g = d_dist->all_reduce_sum({ sum, static_cast<double>(total) }); // all ranks' frames
        r.metric = g[0] / g[1];
        r.count = static_cast<int64_t>(g[1]);
        r.obs = torch::cat(obs, 0);
        if (!logits.empty())
            r.logits = torch::cat(logits, 0);
        if (!delay.empty())
            r.delay = torch::cat(delay, 0);
        return r;
    }

    void print(const std::string& line) const
    {
        if (d_log && d_s.verbose && d_dist->rank() == 0)
            *d_log << line << std::endl;
    }

    // H + (Y - H)·scale: the noise of each element scaled (scale N x M, or B x N x M).
    static torch::Tensor scale_noise(const torch::Tensor& y, const torch::Tensor& h, const torch::Tensor& scale)
    {
        return h + (y - h) * scale.unsqueeze(-3);
    }

    // The N x M noise scales of pilots at flat indices `idx` with energies `power`
    // (1 elsewhere); undefined when every pilot has energy 1 (nothing to scale).
    torch::Tensor noise_grid(const std::vector<int64_t>& idx, const std::vector<double>& power) const
    {
        if (std::all_of(power.begin(), power.end(), [](double p) { return p == 1.0; }))
            return {};
        auto g = torch::ones({ d_n * d_m });
        for (size_t k = 0; k < idx.size(); ++k)
            g[idx[k]] = static_cast<float>(pilot_mask::noise_scale_of_power(power[k]));
        return g.view({ d_n, d_m });
    }

    // The 0/1 N x M mask of flat indices.
    torch::Tensor mask_grid(const std::vector<int64_t>& idx) const
    {
        auto m = torch::zeros({ d_n * d_m });
        m.index_fill_(0, torch::tensor(idx, torch::kLong), 1.0f);
        return m.view({ d_n, d_m });
    }

    float d_tau_min = 0.0f;
    json d_history = json::array();
};

training_result trainer::run()
{
    const auto t0 = clock_type::now();
    d_s.validate();
    if (d_s.threads > 0) {
        torch::set_num_threads(d_s.threads);
    }
    const std::string heap = tune_malloc_for_tensors(); // before the first tensor
    d_dist = std::make_unique<training::distributed_context>(d_s.distributed);
    if (d_log && d_s.verbose && d_dist->rank() == 0)
        *d_log << "allocator: " << heap << std::endl;
    const uint64_t rank_seed = d_dist->rank_seed(d_s.seed); // d_s.seed on rank 0
    torch::manual_seed(rank_seed);
    d_n = d_s.frame.n_symbols;
    d_m = d_s.frame.n_subcarriers;
    const scene sc = d_s.scene_spec ? *d_s.scene_spec : default_scene();
    if (d_s.task == task_kind::classify && sc.label_classes().size() < 2)
        fail("classify needs a scene whose target of interest can be one of at least two classes (" +
             d_s.scene_source + " has " + std::to_string(sc.label_classes().size()) + ")");

    std::optional<pilot_mask> given_mask;
    if (!d_s.mask_file.empty() && !d_s.mask_pattern.empty())
        fail("give either a mask file or a mask pattern, not both");
    if (!d_s.mask_pattern.empty())
        given_mask = pilot_mask::from_pattern(d_s.mask_pattern, d_s.frame, d_s.n_pilots, d_s.seed);
    if (!d_s.mask_file.empty()) {
        given_mask = pilot_mask::load(d_s.mask_file);
        given_mask->check_frame(d_s.frame, "training settings: mask " + d_s.mask_file);
        if (given_mask->size() != d_s.n_pilots)
            fail("mask " + d_s.mask_file + " has " + std::to_string(given_mask->size()) + " pilots but --pilots is " +
                 std::to_string(d_s.n_pilots));
    }

    if (d_dist->active()) { // this rank's share of the frames, from its own seed
        training_settings mine = d_s;
        mine.frames = static_cast<int>(d_dist->share(d_s.frames));
        mine.seed = rank_seed;
        d_data = training::make_data(mine, sc);
        const auto lo = d_dist->all_reduce_min({ d_data.delay_min, -d_data.delay_max });
        d_data.delay_min = lo[0]; // the delay grid from all ranks' frames
        d_data.delay_max = -lo[1];
    } else {
        d_data = training::make_data(d_s, sc);
    }
    {
        std::ostringstream os;
        os << "data: " << d_data.train.size() << " train / " << d_data.val.size() << " val / "
           << d_data.test.size() << " test frames from " << d_s.scene_source << " ("
           << std::fixed << std::setprecision(1) << since(t0) << " s)";
        if (d_data.train.streamed())
            os << "; the training frames are streamed (" << std::setprecision(1)
               << d_data.train.held_bytes() / 1073741824.0
               << " GiB if held): each batch's are computed again from their drawn paths";
        if (d_dist->active())
            os << " on rank 0 of " << d_dist->world_size() << " (each rank draws its own share)";
        if (d_s.radio)
            os << "; observed through the radio " << d_s.radio_source;
        print(os.str());
    }
    // Fixed noise for validation and test, from their own generators.
    auto val_gen = at::detail::createCPUGenerator(rank_seed * 2654435761ULL + 17);
    auto val_noisy = training::observe(
        d_data.val.h, training::draw_noise_variance(d_data.val.size(), d_s.snr_min_db, d_s.snr_max_db, val_gen),
        d_data.val.delay, d_s, val_gen);

    nn::task_decoder task_dec = make_task_decoder(sc);
    d_dist->broadcast_module(*task_dec); // identical start: rank 0's weights
    if (d_s.task == task_kind::delay)
        d_tau_min = static_cast<float>(
            std::dynamic_pointer_cast<nn::delay_decoder_module>(task_dec)->settings().tau_min_index);

    std::vector<int64_t> mask_idx;
    std::vector<double> mask_power; // the pilots' energies, in the order of mask_idx
    json mask_origin;
    const int64_t n_train = d_data.train.size();
    const int64_t n_templates = d_s.task != task_kind::classify ? 0
                                : d_s.classifier.template_frames == -1 ? n_train
                                                                       : d_s.classifier.template_frames;
    if (n_templates > 0 && d_dist->active())
        fail("classifier template_frames needs a single process: each rank draws frames of its own, and the bank "
             "is one set of training frames");
    if (n_templates > n_train)
        fail("classifier template_frames is " + std::to_string(n_templates) + " but only " + std::to_string(n_train) +
             " frames train (--frames " + std::to_string(d_s.frames) + " less the validation and test frames)");
    const int64_t batch = d_s.batch / d_dist->world_size(); // this rank's part of the global batch
    // Every rank runs the same number of steps (collectives pair up).
    const int64_t steps = static_cast<int64_t>(
        d_dist->all_reduce_min({ static_cast<double>(std::max<int64_t>(1, n_train / batch)) })[0]);
    // Frames one epoch trains on, all ranks (a set smaller than the batch is one short step).
    const double epoch_frames = static_cast<double>(steps * std::min(batch, n_train) * d_dist->world_size());
    int epoch_no = 0;
    int mask_epochs_left = 0; // phase 1's unused epochs, given to phase 2

    auto train_epoch = [&](auto&& forward_loss, torch::optim::Optimizer& opt,
                           const std::vector<std::shared_ptr<torch::nn::Module>>& modules) {
        double sum = 0.0;
        auto perm = torch::randperm(n_train, torch::kLong);
        struct step_batch {
            torch::Tensor idx, h, y;
        };
        auto batch_of_step = [&](int64_t st) {
            step_batch b;
            b.idx = perm.slice(0, st * batch, std::min<int64_t>(n_train, (st + 1) * batch));
            b.h = d_data.train.frames(b.idx);
            b.y = training::observe(
                b.h, training::draw_noise_variance(b.idx.size(0), d_s.snr_min_db, d_s.snr_max_db, c10::nullopt),
                d_data.train.delay.index_select(0, b.idx), d_s, c10::nullopt);
            return b;
        };
        step_batch next = batch_of_step(0);
        for (int64_t st = 0; st < steps; ++st) {
            const step_batch cur = std::move(next);
            opt.zero_grad();
            torch::Tensor l = forward_loss(cur.y, cur.h, cur.idx);
            l.backward();
            // Mean over the ranks (batch-norm statistics too). The next step's batch is
            // drawn while the gradients travel and a slower rank catches up; the random
            // draws keep their order (this step's forward, then the next batch), so a
            // single rank trains bit-identically either way.
            d_dist->start_gradient_all_reduce(opt, modules);
            if (st + 1 < steps)
                next = batch_of_step(st + 1);
            d_dist->finish_gradient_all_reduce();
            opt.step();
            sum += l.item<double>();
        }
        return d_dist->all_reduce_sum({ sum / steps })[0] / d_dist->world_size();
    };

    // ---- Phase 1: learn the mask together with the objective's decoder.
    if (!given_mask) {
        const bool mse = d_s.objective == "mse";
        nn::task_decoder dec1 =
            mse ? std::make_shared<nn::reconstruction_decoder_module>(d_n, d_m, d_s.n_pilots, d_s.reconstruction)
                : task_dec;
        const bool learn_power = d_s.pilot_power == "learned";
        const double floor = d_s.pilot_power_floor;
        nn::semantic_encoder enc(d_s.n_pilots, d_n, d_m, d_s.encoder, learn_power,
                                 d_s.frame.guard_subcarriers);
        d_dist->broadcast_module(*enc);
        if (mse)
            d_dist->broadcast_module(*dec1);
        std::vector<torch::optim::OptimizerParamGroup> groups;
        groups.emplace_back(dec1->parameters(), std::make_unique<torch::optim::AdamOptions>(d_s.lr));
        groups.emplace_back(enc->parameters(),
                            std::make_unique<torch::optim::AdamOptions>(d_s.lr * d_s.encoder.lr_scale));
        torch::optim::Adam opt(groups, torch::optim::AdamOptions(d_s.lr));
        double tau = d_s.encoder.temperature_start;
        const bool hib = higher_is_better(mse);
        double best = hib ? -1e300 : 1e300;
        int since_best = 0;
        std::vector<int64_t> best_mask;
        std::vector<double> best_power;
        auto best_state = snapshot(dec1);
        mask_settle_rule settle(d_s.mask_settle_epochs);
        for (int e = 0; e < d_s.epochs; ++e) {
            const auto te = clock_type::now();
            const auto ce = std::clock();
            const double ce_w = d_s.delay_ce_weight;
            const bool hard = e >= d_s.encoder.soft_epochs; // hard 0/1 masks unless in the soft warm-up
            const double l = train_epoch(
                [&](const torch::Tensor& y, const torch::Tensor& h, const torch::Tensor& idx) {
                    torch::Tensor in, mask;
                    if (learn_power) {
                        // Pilot k observes H + noise/sqrt(p_k) (pilot_mask::noise_scale_of_power).
                        auto sel = enc->sample(tau, hard);
                        mask = nn::semantic_encoder_module::mask_from_selection(sel, d_n, d_m);
                        const auto scale = torch::matmul(torch::rsqrt(enc->pilot_power(sel, floor)), sel);
                        in = h * mask + (y - h) * scale.view({ d_n, d_m });
                    } else {
                        mask = enc->sample_mask(tau, hard); // without the N_p x N·M selection when large
                        in = y * mask;
                    }
                    auto out = dec1->forward(in, mask);
                    auto task_l = loss(out, d_data.train, idx, h, ce_w);
                    if (d_s.encoder.collision_weight > 0.0)
                        task_l = task_l + d_s.encoder.collision_weight * enc->collision_penalty(tau);
                    return task_l;
                },
                opt, { dec1, enc.ptr() });
            const double fps = epoch_frames / since(te); // training frames/s, all ranks
            const double cpu_s = cpu_since(ce);         // this process's CPU time
            mask_idx = enc->final_indices();
            const auto power = enc->final_power(mask_idx, floor);
            const auto v = evaluate(dec1, mask_idx, d_data.val, val_noisy, 0, noise_grid(mask_idx, power));
            const int distinct = enc->distinct_argmax();
            std::ostringstream os;
            const auto used = mask_grid(mask_idx);
            const int n_sub = (used.sum(0) > 0).sum().item<int>(), n_sym = (used.sum(1) > 0).sum().item<int>();
            os << std::fixed << "epoch " << std::setw(3) << ++epoch_no << " [mask+" << (mse ? "mse" : "task")
               << (hard ? "" : ", soft") << "] loss " << std::setprecision(4) << l << "  val "
               << (mse ? "mse " : (hib ? "acc " : "mae ")) << std::setprecision(4) << v.metric << "  temp "
               << std::setprecision(3) << tau << "  distinct " << distinct << "/" << d_s.n_pilots << "  symbols " << n_sym
               << " subcarriers " << n_sub << "  " << std::setprecision(1) << since(te) << " s  " << std::setprecision(0)
               << fps << " frames/s  " << std::setprecision(1) << cpu_s << " CPU-s";
            const auto [p_lo, p_hi] = std::minmax_element(power.begin(), power.end());
            if (learn_power)
                os << std::setprecision(2) << "  power " << *p_lo << ".." << *p_hi;
            print(os.str());
            d_history.push_back({ { "epoch", epoch_no }, { "phase", "mask" }, { "loss", l }, { "val", v.metric },
                                  { "temperature", tau }, { "distinct", distinct }, { "symbols", n_sym },
                                  { "subcarriers", n_sub }, { "hard", hard }, { "seconds", since(te) },
                                  { "cpu_seconds", cpu_s }, { "train_frames_per_s", fps } });
            if (learn_power)
                d_history.back()["pilot_power_range"] = { *p_lo, *p_hi };
            const bool at_floor = tau <= d_s.encoder.temperature_floor * (1 + 1e-9);
            tau = std::max(d_s.encoder.temperature_floor, tau * d_s.encoder.temperature_decay);
            const bool better = hib ? v.metric > best : v.metric < best;
            if (better) {
                best = v.metric;
                best_mask = mask_idx;
                best_power = power;
                best_state = snapshot(dec1);
            }
            since_best = better ? 0 : since_best + 1;
            const bool settled = settle.settled_after(mask_idx);
            // (Every rank holds the same scores and validation sums: they stop together.)
            mask_epochs_left = d_s.epochs - e - 1;
            if (at_floor && since_best >= d_s.patience) {
                print("early stop (mask phase): no improvement for " + std::to_string(since_best) + " epochs; " +
                      std::to_string(mask_epochs_left) + " epochs go to the decoder phase");
                break;
            }
            if (settled && mask_epochs_left > 0) {
                print("mask settled: unchanged for " + std::to_string(settle.unchanged()) + " epochs; " +
                      std::to_string(mask_epochs_left) + " epochs go to the decoder phase");
                break;
            }
        }
        // The mask (and decoder) of the best validation epoch: the final greedy mask is
        // what validation scores, so this is the best distinct mask seen.
        if (!best_mask.empty()) {
            mask_idx = best_mask;
            mask_power = best_power;
            restore(dec1, best_state);
        } else {
            mask_power = enc->final_power(mask_idx, floor);
        }
        {
            // Mask order: row-major (n, m), each pilot keeping its energy.
            std::vector<size_t> order(mask_idx.size());
            for (size_t i = 0; i < order.size(); ++i)
                order[i] = i;
            std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return mask_idx[a] < mask_idx[b]; });
            std::vector<int64_t> idx;
            std::vector<double> pw;
            for (size_t i : order) {
                idx.push_back(mask_idx[i]);
                pw.push_back(mask_power[i]);
            }
            mask_idx = std::move(idx);
            mask_power = std::move(pw);
        }
        mask_origin = { { "kind", "learned" },
                        { "objective", d_s.objective },
                        { "best_val", best },
                        { "method", enc->is_topk() ? "gumbel top-k over symbol x subcarrier scores (top N_p of Z)"
                                                   : "gumbel-softmax heads, greedy distinct assignment" },
                        { "encoder", d_s.encoder.to_json() },
                        { "mask_epochs_run", d_s.epochs - mask_epochs_left },
                        { "seed", d_s.seed } };
        if (learn_power)
            mask_origin["pilot_power"] = { { "kind", "learned" }, { "floor", floor } };
    } else {
        for (int i : given_mask->flat_indices())
            mask_idx.push_back(i);
        mask_power = given_mask->power();
        mask_origin = given_mask->origin();
    }

    // ---- Phase 2: the task decoder on the fixed mask.
    const auto mask_t = mask_grid(mask_idx);
    const auto noise_t = noise_grid(mask_idx, mask_power); // undefined for equal power
    const int epochs2 = given_mask ? d_s.epochs : d_s.decoder_epochs + mask_epochs_left;
    // The template bank (template_bank.h): the first T training frames' noiseless pilots on
    // the final mask. While the decoder trains, each frame is matched leave-one-out (its own
    // template would match it exactly, which no test frame does).
    std::shared_ptr<nn::template_bank_module> bank;
    torch::Tensor bank_row; // training frame -> its row in the bank (-1: not in it)
    if (n_templates > 0) {
        bank = std::dynamic_pointer_cast<nn::spectral_classifier_decoder_module>(task_dec)->template_bank();
        const auto flat = torch::tensor(mask_idx, torch::kLong);
        const auto pilots = d_data.train.pilots(n_templates, flat);
        bank_row = torch::full({ n_train }, -1, torch::kLong);
        bank_row.slice(0, 0, n_templates).copy_(bank->set(pilots, d_data.train.label.slice(0, 0, n_templates)));
        print("template bank: " + std::to_string(n_templates) + " training frames x " + std::to_string(mask_idx.size()) +
              " pilots");
    }
    {
        torch::optim::Adam opt(task_dec->parameters(), torch::optim::AdamOptions(d_s.lr));
        const bool hib = higher_is_better(false);
        double best = hib ? -1e300 : 1e300;
        auto best_state = snapshot(task_dec);
        int since_best = 0;
        for (int e = 0; e < epochs2; ++e) {
            const auto te = clock_type::now();
            const auto ce = std::clock();
            // Cosine learning rate from lr to lr * lr_final_scale; the delay loss moves
            // from cross-entropy towards L1 over the same schedule.
            const double frac = epochs2 > 1 ? static_cast<double>(e) / (epochs2 - 1) : 1.0;
            const double c = 0.5 * (1 + std::cos(M_PI * frac));
            const double lr = d_s.lr * (d_s.lr_final_scale + (1 - d_s.lr_final_scale) * c);
            for (auto& g : opt.param_groups())
                static_cast<torch::optim::AdamOptions&>(g.options()).lr(lr);
            const double ce_w = d_s.delay_ce_weight_final + (d_s.delay_ce_weight - d_s.delay_ce_weight_final) * c;
            const double l = train_epoch(
                [&](const torch::Tensor& y, const torch::Tensor& h, const torch::Tensor& idx) {
                    const auto in = noise_t.defined() ? scale_noise(y, h, noise_t) : y; // σ/sqrt(p_k)
                    if (bank)
                        bank->exclude(bank_row.index_select(0, idx));
                    auto out = task_dec->forward(in * mask_t, mask_t);
                    if (bank)
                        bank->exclude({});
                    return loss(out, d_data.train, idx, h, ce_w);
                },
                opt, { task_dec });
            const double fps = epoch_frames / since(te); // training frames/s, all ranks
            const double cpu_s = cpu_since(ce);         // this process's CPU time
            const auto v = evaluate(task_dec, mask_idx, d_data.val, val_noisy, 0, noise_t);
            std::ostringstream os;
            os << std::fixed << "epoch " << std::setw(3) << ++epoch_no << " [decoder] loss " << std::setprecision(4)
               << l << "  val " << (hib ? "acc " : "mae ") << v.metric << "  lr " << std::setprecision(5) << lr
               << "  distinct " << mask_idx.size() << "/" << d_s.n_pilots << "  " << std::setprecision(1)
               << since(te) << " s  " << std::setprecision(0) << fps << " frames/s  " << std::setprecision(1) << cpu_s
               << " CPU-s";
            print(os.str());
            d_history.push_back({ { "epoch", epoch_no }, { "phase", "decoder" }, { "loss", l }, { "val", v.metric },
                                  { "lr", lr }, { "seconds", since(te) }, { "cpu_seconds", cpu_s },
                                  { "train_frames_per_s", fps } });
            const bool better = hib ? v.metric > best : v.metric < best;
            if (better) {
                best = v.metric;
                best_state = snapshot(task_dec);
            }
            since_best = better ? 0 : since_best + 1;
            if (since_best >= d_s.patience) {
                print("early stop (decoder phase): no improvement for " + std::to_string(since_best) + " epochs");
                break;
            }
        }
        restore(task_dec, best_state);
    }

    d_dist->check_in_sync({ task_dec }, "training");

    // ---- Test metrics (each rank scores its own test frames; sums over all ranks).
    training_result res;
    json metrics = json::object();
    auto test_gen = at::detail::createCPUGenerator(rank_seed * 2654435761ULL + 29);
    auto score = [&](double lo, double hi, bool keep) {
        auto noisy = training::observe(
            d_data.test.h, training::draw_noise_variance(d_data.test.size(), lo, hi, test_gen), d_data.test.delay, d_s,
            test_gen);
        // eval_frames over all ranks (0 = every test frame); each rank scores its share.
        const int64_t limit = keep || d_s.eval_frames <= 0 ? 0 : std::max<int64_t>(1, d_dist->share(d_s.eval_frames));
        const auto r = evaluate(task_dec, mask_idx, d_data.test, noisy, limit, noise_t);
        const int64_t n = r.obs.size(0); // this rank's frames
        json m = { { "snr_min_db", lo }, { "snr_max_db", hi }, { "frames", r.count } };
        if (d_s.task == task_kind::classify) {
            m["accuracy"] = r.metric;
        } else {
            m["mae_index"] = r.metric;
            m["mae_m"] = r.metric * d_s.frame.range_per_delay_index_m();
            auto err = d_dist->all_gather(r.delay - d_data.test.delay.slice(0, 0, n));
            m["rmse_index"] = std::sqrt((err * err).mean().item<double>());
            m["median_abs_error_index"] = err.abs().median().item<double>();
        }
        if (keep) {
            res.n_test = static_cast<int>(n);
            auto o = r.obs.contiguous();
            auto po = reinterpret_cast<const gr_complex*>(o.data_ptr<float>());
            res.test_obs.assign(po, po + n * d_s.n_pilots);
            if (d_s.task == task_kind::classify) {
                auto p = torch::softmax(r.logits, 1).contiguous();
                res.test_probs.assign(p.data_ptr<float>(), p.data_ptr<float>() + p.numel());
                auto lab = d_data.test.label.slice(0, 0, n);
                for (int64_t i = 0; i < n; ++i)
                    res.test_labels.push_back(static_cast<int>(lab[i].item<int64_t>()));
            } else {
                auto d = r.delay.to(torch::kDouble).contiguous();
                res.test_delay_index.assign(d.data_ptr<double>(), d.data_ptr<double>() + n);
                auto t = d_data.test.delay.slice(0, 0, n).to(torch::kDouble).contiguous();
                res.test_truth_index.assign(t.data_ptr<double>(), t.data_ptr<double>() + n);
            }
        }
        return m;
    };
    metrics["test"] = score(d_s.snr_min_db, d_s.snr_max_db, true);
    metrics["test_by_snr"] = json::array();
    for (double snr : d_s.eval_snr_db)
        metrics["test_by_snr"].push_back(score(snr, snr, false));

    // ---- The bundle.
    std::vector<pilot_position> pos;
    for (auto i : mask_idx)
        pos.push_back({ static_cast<int>(i / d_m), static_cast<int>(i % d_m) });
    model_bundle& b = res.bundle;
    b.task = d_s.task;
    b.class_names = d_s.task == task_kind::classify ? d_data.class_names : std::vector<std::string>{};
    b.library = d_s.task == task_kind::classify ? sc.library_ptr() : nullptr; // bundle.json's class_library
    b.frame = d_s.frame;
    b.mask = given_mask ? *given_mask
                        : pilot_mask(d_n, d_m, pos, gr_complex(1.0f, 0.0f), mask_origin, "learned mask",
                                     d_s.pilot_power == "learned" ? mask_power : std::vector<double>{});
    if (!d_s.pilot_phases.empty()) // what is sent, not what the decoder sees: training is the same
        b.mask = b.mask.with_phases(d_s.pilot_phases, "training settings: pilot_phases");
    b.decoder = task_dec->describe();
    b.training = d_s.to_json();
    b.training["scene"] = sc.to_json();
    b.training["epochs_run"] = epoch_no;
    b.training["history"] = d_history;
    res.seconds = since(t0);
    b.training["wall_time_s"] = res.seconds;
    b.metrics = metrics;
    res.history = d_history;
    if (d_dist->active()) {
        const double steps_run = static_cast<double>(d_dist->gradient_calls());
        b.training["distributed"] = { { "gradient_allreduce_ms_per_step",
                                        steps_run > 0 ? 1e3 * d_dist->gradient_seconds() / steps_run : 0.0 },
                                      { "gradient_floats_per_step", d_dist->gradient_floats() },
                                      { "rendezvous", d_s.distributed.store_file.empty() ? "TCPStore" : "FileStore" } };
        std::ostringstream os;
        os << std::fixed << std::setprecision(2) << "gradient all-reduce over " << d_dist->world_size()
           << " ranks: " << b.training["distributed"]["gradient_allreduce_ms_per_step"].get<double>()
           << " ms/step (" << d_dist->gradient_floats() << " floats), " << d_dist->gradient_seconds() << " s of "
           << since(t0) << " s";
        print(os.str());
    }
    if (!d_s.out_dir.empty() && d_dist->rank() == 0) { // rank 0 alone writes
        b.save(d_s.out_dir);
        nn::save_module(task_dec, d_s.out_dir + "/" + model_bundle::weights_file);
        b.directory = d_s.out_dir;
    }
    std::ostringstream os;
    os << std::fixed << std::setprecision(4) << "done in " << std::setprecision(1) << res.seconds << " s: test "
       << metrics["test"].dump();
    print(os.str());
    for (const auto& m : metrics["test_by_snr"])
        print("  " + m.dump());
    return res;
}

} // namespace

void training_settings::validate() const
{
    if (objective != "task" && objective != "mse")
        fail("objective must be \"task\" or \"mse\", got \"" + objective + "\"");
    if (training_data != "hold" && training_data != "stream" && training_data != "auto")
        fail("training_data must be \"hold\", \"stream\" or \"auto\", got \"" + training_data + "\"");
    if (pilot_power != "equal" && pilot_power != "learned")
        fail("pilot_power must be \"equal\" or \"learned\", got \"" + pilot_power + "\"");
    if (pilot_power == "learned" && (!mask_file.empty() || !mask_pattern.empty()))
        fail("pilot_power \"learned\" needs a learned mask (no mask file or pattern); a mask file's own "
             "\"power\" list is used as it is");
    if (!(pilot_power_floor >= 0.0 && pilot_power_floor < 1.0))
        fail("pilot_power_floor must be in [0, 1), got " + std::to_string(pilot_power_floor));
    if (!pilot_phases.empty() && pilot_phases != "zero") {
        const auto names = pilot_mask::phase_sequence_names(); // what pilot_mask::with_phases() takes
        if (std::find(names.begin(), names.end(), pilot_phases) == names.end()) {
            std::string known = "\"zero\"";
            for (const auto& name : names)
                known += " or \"" + name + "\"";
            fail("pilot_phases must be " + known + " (or empty: as the mask has them), got \"" + pilot_phases + "\"");
        }
    }
    frame.validate();
    if (radio) {
        radio->validate();
        if (radio->sfo_ppm != 0.0)
            fail("radio " + radio_source + ": sfo_ppm is " + std::to_string(radio->sfo_ppm) +
                 ", but training draws no sample clock offset (set it to 0)");
        if (pilot_power == "learned")
            fail("pilot_power \"learned\" scales each pilot's noise by its energy, which a radio's impairments do "
                 "not follow: train for a radio with equal pilot power");
    }
    if (n_pilots < 1 || n_pilots > frame.grid_size())
        fail("pilots must be in [1, N*M = " + std::to_string(frame.grid_size()) + "], got " +
             std::to_string(n_pilots));
    if (n_pilots > frame.usable_elements())
        fail("pilots: " + std::to_string(n_pilots) + " pilots do not fit the N*(M - guards) = " +
             std::to_string(frame.usable_elements()) + " resource elements off the frame's " +
             std::to_string(frame.guard_subcarriers.size()) + " guard subcarriers");
    if (std::isnan(snr_min_db) || std::isnan(snr_max_db) || snr_min_db > snr_max_db)
        fail("need snr_min_db <= snr_max_db (not NaN)");
    if (frames < 10)
        fail("frames must be >= 10 (split 8:1:1), got " + std::to_string(frames));
    if (epochs < 0 || decoder_epochs < 0)
        fail("epochs must be >= 0");
    if (mask_settle_epochs < 0)
        fail("mask_settle_epochs must be >= 0 (0: phase 1 runs every mask epoch), got " +
             std::to_string(mask_settle_epochs));
    if (batch < 1)
        fail("batch must be >= 1");
    for (const auto& [name, w] : { std::pair<const char*, double>{ "delay_ce_weight", delay_ce_weight },
                                   { "delay_ce_weight_final", delay_ce_weight_final } })
        if (!(w >= 0.0 && std::isfinite(w)))
            fail(std::string(name) + " must be finite and >= 0, got " + std::to_string(w));
    distributed.validate();
    if (batch % distributed.world_size != 0)
        fail("batch " + std::to_string(batch) + " (global) must be a multiple of the world size " +
             std::to_string(distributed.world_size));
    if (frames / distributed.world_size < 10)
        fail("frames must give each of the " + std::to_string(distributed.world_size) +
             " ranks >= 10 frames (split 8:1:1), got " + std::to_string(frames));
    if (!(lr > 0.0) || !std::isfinite(lr))
        fail("lr must be a positive finite number");
    if (!(delay_spacing > 0.0))
        fail("delay_spacing must be positive");
    if (!(encoder.temperature_floor > 0.0) || encoder.temperature_start < encoder.temperature_floor)
        fail("need 0 < temperature floor <= temperature start");
    if (!nn::encoder_settings::known_kind(encoder.kind))
        fail("encoder kind must be \"gumbel_topk\" or \"gumbel_heads\", got \"" + encoder.kind + "\"");
    if (encoder.soft_epochs < 0)
        fail("soft_epochs must be >= 0");
    if (!(encoder.lr_scale > 0.0) || !std::isfinite(encoder.lr_scale))
        fail("encoder lr_scale must be a positive finite number");
    if (!(encoder.collision_weight >= 0.0) || !std::isfinite(encoder.collision_weight))
        fail("collision_weight must be a finite number >= 0");
    classifier.validate("training settings: classifier");
    if (task == task_kind::classify && classifier.architecture == "spectral" && classifier.doppler_bins < frame.n_symbols)
        fail("classifier doppler_bins must be >= the frame's " + std::to_string(frame.n_symbols) + " symbols");
}

json training_settings::to_json() const
{
    json j = { { "objective", objective },
               { "n_pilots", n_pilots },
               { "mask_file", mask_file },
               { "mask_pattern", mask_pattern },
               { "pilot_power", pilot_power },
               { "scene_source", scene_source },
               { "snr_min_db", snr_min_db },
               { "snr_max_db", snr_max_db },
               { "frames", frames },
               { "split", "8:1:1" },
               { "epochs", epochs },
               { "decoder_epochs", decoder_epochs },
               { "batch", batch },
               { "world_size", distributed.world_size },
               { "batch_per_rank", batch / distributed.world_size },
               { "data_per_rank", distributed.world_size > 1
                                      ? "each rank draws frames/world_size of the frames from its own seed (rank 0: seed)"
                                      : "one process" },
               { "lr", lr },
               { "lr_schedule", "phase 1 constant; phase 2 cosine to lr*" + std::to_string(lr_final_scale) },
               { "patience", patience },
               { "mask_settle_epochs", mask_settle_epochs },
               { "threads", threads },
               { "seed", seed },
               { "delay_spacing", delay_spacing },
               { "delay_margin", delay_margin },
               { "delay_ce_weight", delay_ce_weight },
               { "delay_ce_weight_final", delay_ce_weight_final },
               { "lr_final_scale", lr_final_scale },
               { "eval_snr_db", eval_snr_db },
               { "eval_frames", eval_frames },
               { "encoder", encoder.to_json() },
               { "reconstruction", reconstruction.to_json() },
               { "command_line", command_line } };
    if (pilot_power == "learned")
        j["pilot_power_floor"] = pilot_power_floor;
    if (!pilot_phases.empty())
        j["pilot_phases"] = pilot_phases;
    if (radio) { // absent: the ideal radio
        j["radio"] = radio->to_json();
        j["radio_source"] = radio_source;
    }
    return j;
}

training_settings training_settings::from_bundle(const model_bundle& b)
{
    const std::string path = (b.directory.empty() ? std::string("(in memory)") : b.directory) + "/" +
                             model_bundle::bundle_file;
    const json& t = b.training;
    auto bad = [&](const std::string& key, const std::string& problem) {
        throw std::invalid_argument(path + ": training." + key + ": " + problem);
    };
    if (!t.is_object() || t.empty())
        bad("", "no training record: the bundle cannot be trained again from it");
    // A recorded value (required, or a default for keys older bundles lack) of type T.
    auto get = [&](const std::string& key, auto fallback, bool required) {
        using T = decltype(fallback);
        if (!t.contains(key)) {
            if (required)
                bad(key, "missing");
            return fallback;
        }
        try {
            return t.at(key).get<T>();
        } catch (const json::exception&) {
            bad(key, "has the wrong type: " + t.at(key).dump());
        }
        return fallback;
    };
    training_settings s;
    s.task = b.task;
    s.frame = b.frame;
    s.objective = get("objective", s.objective, true);
    s.n_pilots = get("n_pilots", s.n_pilots, true);
    s.mask_pattern = get("mask_pattern", std::string(), false);
    s.pilot_power = get("pilot_power", std::string("equal"), false); // absent: trained before the setting
    s.pilot_power_floor = get("pilot_power_floor", s.pilot_power_floor, false);
    s.pilot_phases = get("pilot_phases", std::string(), false); // absent: as the mask has them
    if (!get("mask_file", std::string(), false).empty())
        s.mask_file = b.directory + "/" + b.mask_name; // the given mask, as the bundle holds it
    s.snr_min_db = get("snr_min_db", s.snr_min_db, true);
    s.snr_max_db = get("snr_max_db", s.snr_max_db, true);
    s.frames = get("frames", s.frames, true);
    s.epochs = get("epochs", s.epochs, true);
    s.decoder_epochs = get("decoder_epochs", s.decoder_epochs, true);
    s.batch = get("batch", s.batch, true);
    s.lr = get("lr", s.lr, true);
    s.patience = get("patience", s.patience, true);
    s.mask_settle_epochs = get("mask_settle_epochs", 0, false); // absent: trained before the rule
    s.threads = get("threads", s.threads, false);
    s.seed = get("seed", s.seed, true);
    s.delay_spacing = get("delay_spacing", s.delay_spacing, true);
    s.delay_margin = get("delay_margin", s.delay_margin, true);
    s.delay_ce_weight = get("delay_ce_weight", s.delay_ce_weight, false);
    s.delay_ce_weight_final = get("delay_ce_weight_final", s.delay_ce_weight_final, false);
    // Records before lr_final_scale was a key hold it in lr_schedule ("... cosine to lr*0.020000").
    if (t.contains("lr_final_scale")) {
        s.lr_final_scale = get("lr_final_scale", s.lr_final_scale, true);
    } else {
        const auto schedule = get("lr_schedule", std::string(), true);
        const auto star = schedule.rfind("lr*");
        if (star == std::string::npos)
            bad("lr_schedule", "does not name the final learning-rate scale (\"lr*<scale>\"): " + schedule);
        s.lr_final_scale = std::stod(schedule.substr(star + 3));
    }
    // The test points: recorded, or those the metrics were scored at.
    if (t.contains("eval_snr_db")) {
        s.eval_snr_db = get("eval_snr_db", s.eval_snr_db, true);
    } else if (b.metrics.contains("test_by_snr")) {
        s.eval_snr_db.clear();
        for (const auto& m : b.metrics.at("test_by_snr"))
            s.eval_snr_db.push_back(m.value("snr_min_db", 0.0));
    }
    s.eval_frames = get("eval_frames", 0, false);
    if (!t.contains("scene"))
        bad("scene", "missing");
    s.scene_spec = scene::from_json(t.at("scene"), path + ": training.scene");
    s.scene_source = get("scene_source", s.scene_source, false);
    if (t.contains("radio")) { // absent: trained for the ideal radio
        s.radio = front_end_settings::from_json(t.at("radio"), path + ": training.radio");
        s.radio_source = get("radio_source", s.radio_source, false);
    }
    // The encoder only trains a learned mask (older records of fixed-mask runs hold keys
    // the encoder settings no longer have).
    if (s.mask_file.empty() && s.mask_pattern.empty()) {
        if (!t.contains("encoder"))
            bad("encoder", "missing");
        s.encoder = nn::encoder_settings::from_json(t.at("encoder"), path + ": training.encoder");
    }
    if (t.contains("reconstruction"))
        s.reconstruction = nn::reconstruction_settings::from_json(t.at("reconstruction"),
                                                                  path + ": training.reconstruction");
    const json no_settings = json::object();
    const json& settings = b.decoder.contains("settings") ? b.decoder.at("settings") : no_settings;
    if (b.task == task_kind::classify)
        s.classifier = nn::classifier_settings::from_json(settings, path + ": decoder.settings");
    else
        s.delay = nn::delay_settings::from_json(settings, path + ": decoder.settings");
    try {
        s.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(path + ": " + e.what());
    }
    return s;
}

training_result train(const training_settings& settings, std::ostream* log)
{
    trainer t(settings, log);
    return t.run();
}

} // namespace sems
} // namespace gr
