// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: learning a MIMO mask on the azimuth's bound (see mimo_mask_learner.h); the bound
 * over the grid's weights is mimo_bound.h's. */
#include <gnuradio/sems/learning/array/mimo_mask_learner.h>
#include "learning/array/mimo_bound.h"
#include "learning/training/semantic_encoder.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/mimo_angle.h>
#include <gnuradio/sems/core/array/steering.h>
#include <ATen/Parallel.h>
#include <algorithm>
#include <utility>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace gr {
namespace sems {

// Names of their own: the unity build puts this file beside the position trainer.
namespace {

[[noreturn]] void mimo_refuse(const std::string& field, const std::string& problem)
{
    throw std::invalid_argument("MIMO mask learning: " + field + ": " + problem);
}

std::vector<double> uniform_draws(std::mt19937_64& g, double lo, double hi, int count)
{
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<double> out(static_cast<size_t>(count));
    for (auto& x : out)
        x = u(g);
    return out;
}

// A mask of the given pilots and elements, pilot k at pos[k] sent by tx[k] (any order).
mimo_mask mask_of(const mimo_mask& like, std::vector<std::pair<pilot_position, int>> pilots)
{
    std::sort(pilots.begin(), pilots.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<pilot_position> pos;
    std::vector<int> tx;
    for (const auto& [p, t] : pilots) {
        pos.push_back(p);
        tx.push_back(t);
    }
    const pilot_mask& m = like.mask();
    return mimo_mask(pilot_mask(m.n_symbols(), m.n_subcarriers(), pos, m.pilot_symbol(), m.origin(), "learned MIMO mask"),
                     like.n_transmit(), tx, "learned MIMO mask");
}

// The polish after the gradient phase: single changes of one pilot (its element, or a move to
// a free neighbouring resource element off the guards), each kept when it lowers the
// objective, until none does. Gumbel relaxations settle on balanced masks slowly when every
// element's share is a handful of pilots; one flip is what they leave.
mimo_mask polish(const array_geometry& a, mimo_mask m, const mimo_mask_settings& s, double& objective, int& changes)
{
    if (m.n_transmit() != a.n_transmit())
        mimo_refuse("mask", "has " + std::to_string(m.n_transmit()) + " transmit elements and the array " + s.array + " " +
                                std::to_string(a.n_transmit()));
    m.mask().check_frame(s.frame, "MIMO mask polish");
    auto value = [&](const mimo_mask& x) {
        return mimo_mean_crb_rad2(a, x, s.frame, s.azimuth_min_rad, s.azimuth_max_rad, s.eval_azimuths, s.elevation_rad);
    };
    const int n = s.frame.n_symbols, mm = s.frame.n_subcarriers;
    changes = 0;
    for (bool improved = true; improved;) {
        improved = false;
        for (int k = 0; k < m.mask().size(); ++k) {
            std::vector<std::pair<pilot_position, int>> pilots;
            std::vector<char> used(size_t(n) * mm, 0);
            for (int i = 0; i < m.mask().size(); ++i) {
                pilots.emplace_back(m.mask().positions()[size_t(i)], m.transmit()[size_t(i)]);
                used[size_t(pilots.back().first.n) * mm + pilots.back().first.m] = 1;
            }
            const auto [here, element] = pilots[size_t(k)];
            std::vector<std::pair<pilot_position, int>> options;
            for (int j = 0; j < m.n_transmit(); ++j)
                if (j != element)
                    options.emplace_back(here, j);
            for (const auto& [dn, dm] : { std::pair<int, int>{ -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 } }) {
                const pilot_position q{ here.n + dn, here.m + dm };
                if (q.n >= 0 && q.n < n && q.m >= 0 && q.m < mm && !used[size_t(q.n) * mm + q.m] && !s.frame.is_guard(q.m))
                    options.emplace_back(q, element);
            }
            for (const auto& option : options) {
                auto changed = pilots;
                changed[size_t(k)] = option;
                const auto candidate = mask_of(m, changed);
                const double v = value(candidate);
                if (v < objective * (1.0 - 1e-12)) {
                    m = candidate;
                    objective = v;
                    ++changes;
                    improved = true;
                    break; // pilot k's position and index may have changed: the next pilot
                }
            }
        }
    }
    return m;
}

} // namespace

void mimo_mask_settings::validate() const
{
    if (array.empty())
        mimo_refuse("array", "give the array (a preset's name or an array file)");
    frame.validate();
    if (n_pilots < 1 || n_pilots > frame.usable_elements())
        mimo_refuse("n_pilots", "must be in [1, " + std::to_string(frame.usable_elements()) + "] (the frame's usable "
                                "resource elements), got " + std::to_string(n_pilots));
    if (!(std::isfinite(azimuth_min_rad) && std::isfinite(azimuth_max_rad) && azimuth_min_rad < azimuth_max_rad &&
          azimuth_min_rad > -M_PI / 2 && azimuth_max_rad < M_PI / 2))
        mimo_refuse("azimuth", "need −π/2 < azimuth_min_rad < azimuth_max_rad < π/2, got [" +
                                   std::to_string(azimuth_min_rad) + ", " + std::to_string(azimuth_max_rad) + "]");
    if (!(std::isfinite(elevation_rad) && std::fabs(elevation_rad) < M_PI / 2))
        mimo_refuse("elevation_rad", "must be in (−π/2, π/2), got " + std::to_string(elevation_rad));
    if (epochs < 1 || steps < 1 || draws < 1 || eval_azimuths < 1)
        mimo_refuse("epochs", "epochs, steps, draws and eval_azimuths must be >= 1");
    if (!(lr > 0.0 && std::isfinite(lr)))
        mimo_refuse("lr", "must be a finite number > 0, got " + std::to_string(lr));
    if (encoder.kind != "gumbel_topk")
        mimo_refuse("encoder.kind", "must be gumbel_topk (exactly N_p distinct resource elements), got " + encoder.kind);
    if (!(encoder.temperature_floor > 0.0) || encoder.temperature_start < encoder.temperature_floor ||
        !(encoder.temperature_decay > 0.0 && encoder.temperature_decay <= 1.0) || !(encoder.lr_scale > 0.0))
        mimo_refuse("encoder", "need 0 < temperature_floor <= temperature_start, 0 < temperature_decay <= 1, lr_scale > 0");
}

double mimo_mean_crb_rad2(const array_geometry& a, const mimo_mask& m, const frame_settings& fs, double lo, double hi,
                          int count, double elevation_rad)
{
    if (count < 1)
        throw std::invalid_argument("mimo_mean_crb_rad2: count must be >= 1, got " + std::to_string(count));
    double sum = 0.0;
    for (int i = 0; i < count; ++i)
        sum += mimo_angle_crb_rad2(a, m, fs, lo + (hi - lo) * (i + 0.5) / count, elevation_rad, 1.0);
    return sum / count;
}

double mimo_floor_crb_rad2(const array_geometry& a, const frame_settings& fs, int n_pilots, double lo, double hi,
                           int count, double elevation_rad)
{
    if (count < 1 || n_pilots < 1)
        throw std::invalid_argument("mimo_floor_crb_rad2: count and n_pilots must be >= 1");
    const double lambda_min = speed_of_light_mps / (fs.carrier_hz + (fs.n_subcarriers - 1) * fs.subcarrier_spacing_hz());
    double sum = 0.0;
    for (int i = 0; i < count; ++i)
        sum += angle_crb_rad2(a, lo + (hi - lo) * (i + 0.5) / count, elevation_rad, lambda_min,
                              double(n_pilots) / a.n_transmit());
    return sum / count;
}

mimo_mask polish_mimo_mask(const mimo_mask& m, const mimo_mask_settings& s, double* objective, int* changes)
{
    s.validate();
    const array_geometry a = array_geometry::find(s.array);
    double v = mimo_mean_crb_rad2(a, m, s.frame, s.azimuth_min_rad, s.azimuth_max_rad, s.eval_azimuths, s.elevation_rad);
    int n = 0;
    auto out = polish(a, m, s, v, n);
    if (objective)
        *objective = v;
    if (changes)
        *changes = n;
    return out;
}

mimo_mask_result learn_mimo_mask(const mimo_mask_settings& s, std::ostream* log)
{
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    s.validate();
    const array_geometry a = array_geometry::find(s.array);
    const int nt = a.n_transmit();
    if (nt < 2)
        mimo_refuse("array", s.array + " has " + std::to_string(nt) +
                                 " transmit element; a MIMO mask tells two or more apart by their pilots");
    if (s.n_pilots < nt)
        mimo_refuse("n_pilots", std::to_string(s.n_pilots) + " pilots cannot give each of the " + std::to_string(nt) +
                                    " transmit elements one");
    if (s.threads > 0)
        at::set_num_threads(s.threads);
    torch::manual_seed(s.seed);
    auto say = [&](const std::string& line) {
        if (log && s.verbose)
            *log << line << std::endl;
    };
    const frame_settings& fs = s.frame;
    const int n = fs.n_symbols, m = fs.n_subcarriers;
    nn::semantic_encoder enc(s.n_pilots, n, m, s.encoder, false, fs.guard_subcarriers);
    auto tx_logits = torch::zeros({ nt, int64_t(n) * m }, torch::kFloat);
    tx_logits.normal_(0.0, 0.01);
    tx_logits.set_requires_grad(true);
    std::vector<torch::Tensor> params = enc->parameters();
    params.push_back(tx_logits);
    torch::optim::Adam opt(params, torch::optim::AdamOptions(s.lr * s.encoder.lr_scale));
    std::mt19937_64 g(s.seed + 101);

    auto final_mask = [&]() {
        const auto idx = enc->final_indices();
        std::vector<pilot_position> pos;
        for (int64_t i : idx)
            pos.push_back({ int(i / m), int(i % m) });
        const pilot_mask p(n, m, pos, gr_complex(1.0f, 0.0f),
                           { { "kind", "learned_mimo" },
                             { "objective", "azimuth CRB" },
                             { "array", s.array },
                             { "seed", s.seed },
                             { "command", s.command_line } },
                           "learned MIMO mask");
        const auto choice = tx_logits.detach().argmax(0);
        std::vector<int> tx;
        for (const auto& q : p.positions())
            tx.push_back(int(choice[int64_t(q.n) * m + q.m].item<int64_t>()));
        return mimo_mask(p, nt, tx, "learned MIMO mask");
    };

    say("MIMO mask learning: " + std::to_string(s.n_pilots) + " pilots over " + std::to_string(nt) + " transmit x " +
        std::to_string(n) + " symbols x " + std::to_string(m) + " subcarriers of " + s.array + ", azimuths in [" +
        std::to_string(s.azimuth_min_rad) + ", " + std::to_string(s.azimuth_max_rad) + "] rad");
    double tau = s.encoder.temperature_start;
    mimo_mask_result out{ final_mask(), nlohmann::json::array(), std::numeric_limits<double>::infinity(), 0.0 };
    for (int e = 1; e <= s.epochs; ++e) {
        double loss_sum = 0.0;
        for (int step = 0; step < s.steps; ++step) {
            const auto t = nn::mimo_steering_tables(a, fs, uniform_draws(g, s.azimuth_min_rad, s.azimuth_max_rad, s.draws),
                                           s.elevation_rad);
            const auto sel = enc->sample_mask(tau, true);                                 // N x M, 0/1 forward
            const auto assign = nn::gumbel_softmax_st(tx_logits.t(), tau, {}, true).t(); // N_t x N·M, one-hot forward
            const auto w = (assign.view({ nt, n, m }) * sel.unsqueeze(0)).to(torch::kDouble);
            const auto loss = torch::log(nn::mimo_crb_of_weights(t, w).mean());
            opt.zero_grad();
            loss.backward();
            opt.step();
            loss_sum += loss.item<double>();
        }
        const auto mask = final_mask();
        const double objective = mimo_mean_crb_rad2(a, mask, fs, s.azimuth_min_rad, s.azimuth_max_rad, s.eval_azimuths,
                                                    s.elevation_rad);
        const auto counts = mask.pilots_per_element();
        nlohmann::json row = { { "epoch", e },
                               { "loss", loss_sum / s.steps },
                               { "temperature", tau },
                               { "mean_crb_rad2", objective },
                               { "pilots_per_element", counts } };
        out.history.push_back(row);
        std::ostringstream line;
        line << "epoch " << e << "/" << s.epochs << ": root mean CRB at 0 dB " << std::setprecision(5)
             << std::sqrt(objective) << " rad, temperature " << std::setprecision(3) << tau << ", pilots per element";
        for (int c : counts)
            line << " " << c;
        say(line.str());
        if (objective < out.mean_crb_rad2) {
            out.mean_crb_rad2 = objective;
            out.mask = mask;
        }
        tau = std::max(s.encoder.temperature_floor, tau * s.encoder.temperature_decay);
    }
    out.mean_crb_learned_rad2 = out.mean_crb_rad2;
    out.mask = polish(a, out.mask, s, out.mean_crb_rad2, out.polish_changes);
    out.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    std::ostringstream done;
    done << "kept root mean CRB at 0 dB " << std::setprecision(5) << std::sqrt(out.mean_crb_learned_rad2)
         << " rad; after " << out.polish_changes << " single changes " << std::sqrt(out.mean_crb_rad2) << " rad ("
         << std::setprecision(3) << out.seconds << " s)";
    say(done.str());
    return out;
}

} // namespace sems
} // namespace gr
