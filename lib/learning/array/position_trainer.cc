// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: training a position bundle's angle network (see position_trainer.h). */
#include <gnuradio/sems/learning/array/position_trainer.h>
#include "learning/array/angle_network.h"
#include "learning/networks/task_decoder.h"
#include "learning/training/trainer_data.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <ATen/CPUGeneratorImpl.h>
#include <ATen/Parallel.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace gr {
namespace sems {

// Names of their own: the unity build puts this file beside the track trainer and the super-frame learner.
namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& problem)
{
    throw std::invalid_argument("position training: " + field + ": " + problem);
}

// A split's frames as the angle network sees them, noiseless: obs count x K x N_p x 2, and
// each frame's truth (azimuth, delay index) and its target's energy |α|² when the frame is one
// path (NaN otherwise: no bound is defined for it).
struct pilot_set {
    torch::Tensor obs;
    std::vector<double> azimuth, delay_index, gain2;
    int64_t size() const { return obs.size(0); }
};

pilot_set draw_pilots(channel_model& cm, const frame_settings& fs, const pilot_mask& mask, int64_t first, int64_t count)
{
    const int k = cm.n_elements(), np = mask.size();
    const auto flat = mask.flat_indices();
    pilot_set out;
    std::vector<frame_realization> frames;
    frames.reserve(size_t(count));
    for (int64_t f = 0; f < count; ++f) { // drawn in order (a frame is a function of (seed, index))
        frames.push_back(cm.draw(uint64_t(first + f)));
        const auto& t = frames.back().truth;
        out.azimuth.push_back(t.azimuth_rad);
        out.delay_index.push_back(t.delay_index);
        out.gain2.push_back(frames.back().paths.size() == 1 ? double(std::norm(frames.back().paths[0].gain))
                                                             : std::numeric_limits<double>::quiet_NaN());
    }
    out.obs = torch::empty({ count, k, np, 2 }, torch::kFloat);
    auto* dst = reinterpret_cast<gr_complex*>(out.obs.data_ptr<float>());
    at::parallel_for(0, count, 16, [&](int64_t a, int64_t b) {
        std::vector<gr_complex> h(size_t(fs.grid_size()));
        for (int64_t f = a; f < b; ++f)
            for (int e = 0; e < k; ++e) {
                cm.factors(frames[size_t(f)], uint64_t(first + f) * uint64_t(fs.n_symbols), e).fill(h.data());
                gr_complex* row = dst + (size_t(f) * k + size_t(e)) * size_t(np);
                for (int i = 0; i < np; ++i)
                    row[i] = h[size_t(flat[size_t(i)])];
            }
    });
    return out;
}

// The grid index nearest each azimuth (clamped into the grid).
torch::Tensor nearest_index(const std::vector<double>& az, const nn::angle_settings& s)
{
    auto out = torch::empty({ int64_t(az.size()) }, torch::kLong);
    const double step = (s.azimuth_max_rad - s.azimuth_min_rad) / (s.grid - 1);
    for (size_t i = 0; i < az.size(); ++i)
        out[int64_t(i)] = std::clamp<int64_t>(std::llround((az[i] - s.azimuth_min_rad) / step), 0, s.grid - 1);
    return out;
}

torch::Tensor as_tensor(const std::vector<double>& v) { return torch::tensor(v, torch::kDouble).to(torch::kFloat); }

// The network's state, kept at the best validation epoch.
std::vector<torch::Tensor> keep_state(const nn::angle_network& net)
{
    std::vector<torch::Tensor> out;
    for (const auto& p : net->parameters())
        out.push_back(p.detach().clone());
    for (const auto& b : net->buffers())
        out.push_back(b.detach().clone());
    return out;
}

void put_state(nn::angle_network& net, const std::vector<torch::Tensor>& state)
{
    torch::NoGradGuard ng;
    size_t i = 0;
    for (auto& p : net->parameters())
        p.copy_(state[i++]);
    for (auto& b : net->buffers())
        b.copy_(state[i++]);
}

double rms(const std::vector<double>& est, const std::vector<double>& truth)
{
    double se = 0.0;
    for (size_t i = 0; i < est.size(); ++i)
        se += (est[i] - truth[i]) * (est[i] - truth[i]);
    return std::sqrt(se / double(est.size()));
}

double median_abs(const std::vector<double>& est, const std::vector<double>& truth)
{
    std::vector<double> e(est.size());
    for (size_t i = 0; i < est.size(); ++i)
        e[i] = std::fabs(est[i] - truth[i]);
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    return e[e.size() / 2];
}

double mean_abs(const std::vector<double>& est, const std::vector<double>& truth)
{
    double s = 0.0;
    for (size_t i = 0; i < est.size(); ++i)
        s += std::fabs(est[i] - truth[i]);
    return s / double(est.size());
}

} // namespace

scene position_training_settings::default_scene()
{
    random_spec r;
    r.azimuth_min_rad = -0.8;
    r.azimuth_max_rad = 0.8;
    return scene::random(r, std::nullopt, fading_kind::none);
}

void position_training_settings::validate() const
{
    if (delay_bundle.empty())
        refuse("delay_bundle", "give the delay bundle whose decoder reads the beamformed pilots");
    if (array.empty())
        refuse("array", "give the array (a preset's name or an array file)");
    if (frames < 10)
        refuse("frames", "must be at least 10 (split 8:1:1), got " + std::to_string(frames));
    if (epochs < 1 || batch < 1 || patience < 1)
        refuse("epochs", "epochs, batch and patience must be >= 1");
    if (!(lr > 0.0 && std::isfinite(lr)))
        refuse("lr", "must be a finite number > 0");
    if (!(ce_weight >= 0.0 && std::isfinite(ce_weight)))
        refuse("ce_weight", "must be a finite number >= 0");
    if (!(std::isfinite(snr_min_db) && std::isfinite(snr_max_db) && snr_min_db <= snr_max_db))
        refuse("snr", "need finite snr_min_db <= snr_max_db, got [" + std::to_string(snr_min_db) + ", " +
                       std::to_string(snr_max_db) + "]");
    for (double x : eval_snr_db)
        if (!std::isfinite(x))
            refuse("eval_snr_db", "must be finite numbers");
    angle.validate("position training: angle");
}

nlohmann::json position_training_settings::to_json() const
{
    return { { "delay_bundle", delay_bundle }, { "array", array },         { "scene_source", scene_source },
             { "frames", frames },             { "epochs", epochs },       { "batch", batch },
             { "lr", lr },                     { "patience", patience },   { "snr_min_db", snr_min_db },
             { "snr_max_db", snr_max_db },     { "ce_weight", ce_weight }, { "seed", seed },
             { "eval_snr_db", eval_snr_db },   { "command_line", command_line } };
}

position_training_result train_position(const position_training_settings& s, std::ostream* log)
{
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    s.validate();
    if (s.threads > 0)
        at::set_num_threads(s.threads);
    torch::manual_seed(s.seed);
    auto say = [&](const std::string& line) {
        if (log && s.verbose)
            *log << line << std::endl;
    };
    model_bundle delay = model_bundle::load(s.delay_bundle);
    if (delay.task != task_kind::delay)
        refuse("delay_bundle", delay.directory + " is a \"" + task_name(delay.task) + "\" bundle, not a delay bundle");
    if (!delay.position.is_null())
        refuse("delay_bundle", delay.directory + " is already a position bundle: give its delay bundle");
    if (delay.super_frames() != 1)
        refuse("delay_bundle", delay.directory + "'s mask spans " + std::to_string(delay.super_frames()) + " frames");
    const array_geometry array = array_geometry::find(s.array);
    if (array.n_transmit() != 1)
        refuse("array", s.array + " has " + std::to_string(array.n_transmit()) +
                         " transmit elements; the position decoder takes one");
    scene sc = s.scene_spec ? *s.scene_spec : position_training_settings::default_scene();
    if (sc.array() && !(*sc.array() == array))
        refuse("scene", s.scene_source + " names an array of its own that is not " + s.array + ": give one of the two");
    sc = sc.with_array(array);
    const frame_settings& fs = delay.frame;
    const pilot_mask& mask = delay.mask;
    const int k = array.n_receive(), np = mask.size();
    const double lambda = pilot_wavelength_m(fs, mask);

    // Frames 8:1:1, each a function of (seed, index).
    channel_model cm(fs, sc, s.seed);
    const int64_t n_train = int64_t(s.frames) * 8 / 10, n_val = (int64_t(s.frames) - n_train) / 2;
    const int64_t n_test = int64_t(s.frames) - n_train - n_val;
    say("position training: " + std::to_string(k) + "-element array " + s.array + ", " + std::to_string(np) +
        " pilots of " + s.delay_bundle + ", " + std::to_string(s.frames) + " frames");
    const pilot_set train = draw_pilots(cm, fs, mask, 0, n_train);
    const pilot_set val = draw_pilots(cm, fs, mask, n_train, n_val);
    const pilot_set test = draw_pilots(cm, fs, mask, n_train + n_val, n_test);
    for (const auto* set : { &train, &val, &test })
        for (double az : set->azimuth)
            if (!(az >= s.angle.azimuth_min_rad && az <= s.angle.azimuth_max_rad))
                refuse("angle", "the scene draws an azimuth of " + std::to_string(az) + " rad, outside the grid [" +
                                 std::to_string(s.angle.azimuth_min_rad) + ", " + std::to_string(s.angle.azimuth_max_rad) +
                                 "]: widen it or narrow the scene's random.azimuth_rad");

    nn::angle_network net(array, lambda, s.angle);
    torch::optim::Adam opt(net->parameters(), torch::optim::AdamOptions(s.lr));
    auto gen = at::make_generator<at::CPUGeneratorImpl>(s.seed + 17);
    auto val_gen = at::make_generator<at::CPUGeneratorImpl>(s.seed + 29);
    const auto train_idx = nearest_index(train.azimuth, s.angle);
    const auto train_az = as_tensor(train.azimuth);
    const double step = net->step_rad();
    // Validation frames with their noise drawn once.
    const auto val_var = training::draw_noise_variance(n_val, s.snr_min_db, s.snr_max_db, val_gen);
    const auto val_obs = training::add_noise(val.obs, val_var, val_gen);
    const auto val_az = as_tensor(val.azimuth);

    nlohmann::json history = nlohmann::json::array();
    double best = std::numeric_limits<double>::infinity();
    int best_epoch = 0, since = 0;
    auto best_state = keep_state(net);
    for (int epoch = 1; epoch <= s.epochs; ++epoch) {
        const double lr = s.lr * (0.02 + 0.98 * 0.5 * (1.0 + std::cos(M_PI * (epoch - 1) / s.epochs)));
        for (auto& g : opt.param_groups())
            static_cast<torch::optim::AdamOptions&>(g.options()).lr(lr);
        net->train();
        const auto perm = torch::randperm(n_train, gen, torch::kLong);
        double loss_sum = 0.0;
        int64_t steps = 0;
        for (int64_t a = 0; a < n_train; a += s.batch) {
            const int64_t b = std::min<int64_t>(n_train, a + s.batch);
            if (b - a < 2) // BatchNorm's statistics need two frames: a last single frame waits for the next epoch
                break;
            const auto idx = perm.slice(0, a, b);
            const auto var = training::draw_noise_variance(b - a, s.snr_min_db, s.snr_max_db, gen);
            const auto x = training::add_noise(train.obs.index_select(0, idx), var, gen);
            const auto out = net->forward(x);
            auto loss = (out.azimuth - train_az.index_select(0, idx)).abs().mean() / step;
            if (s.ce_weight > 0.0)
                loss = loss + s.ce_weight * torch::nn::functional::cross_entropy(out.logits, train_idx.index_select(0, idx));
            opt.zero_grad();
            loss.backward();
            opt.step();
            loss_sum += loss.item<double>();
            ++steps;
        }
        net->eval();
        double val_rmse = 0.0;
        {
            torch::NoGradGuard ng;
            const auto err = net->forward(val_obs).azimuth - val_az;
            val_rmse = std::sqrt((err * err).mean().item<double>());
        }
        history.push_back({ { "epoch", epoch }, { "lr", lr }, { "loss", loss_sum / std::max<int64_t>(1, steps) },
                            { "val_rmse_rad", val_rmse } });
        std::ostringstream line;
        line << "epoch " << epoch << "/" << s.epochs << ": loss " << std::setprecision(4)
             << loss_sum / std::max<int64_t>(1, steps) << ", validation azimuth RMSE " << val_rmse << " rad";
        say(line.str());
        if (val_rmse < best) {
            best = val_rmse;
            best_epoch = epoch;
            best_state = keep_state(net);
            since = 0;
        } else if (++since >= s.patience) {
            say("early stop: no better validation for " + std::to_string(s.patience) + " epochs");
            break;
        }
    }
    put_state(net, best_state);
    net->eval();
    say("kept epoch " + std::to_string(best_epoch));

    // The bundle: the delay bundle's files and the position record; written, then loaded back
    // so that the test figures are the shipped decoder's own answers.
    namespace fsys = std::filesystem;
    std::string dir = s.out_dir;
    const bool scratch = dir.empty();
    if (scratch)
        dir = (fsys::temp_directory_path() / ("sems_position_" + std::to_string(::getpid()) + "_" +
                                              std::to_string(s.seed))).string();
    std::error_code ec;
    if (fsys::equivalent(dir, delay.directory, ec))
        refuse("out_dir", dir + " is the delay bundle's own directory: write the position bundle elsewhere");
    position_training_result result;
    result.history = history;
    nlohmann::json training = s.to_json();
    training["history"] = history;
    training["best_epoch"] = best_epoch;
    training["scene"] = sc.to_json();
    result.bundle = delay;
    result.bundle.position = { { "array", array.to_json() },
                               { "angle", s.angle.to_json() },
                               { "weights_file", position_estimator::weights_file },
                               { "training", training } };
    result.bundle.save(dir);
    fsys::copy_file(delay.weights_path(), fsys::path(dir) / delay.weights_name, fsys::copy_options::overwrite_existing, ec);
    if (ec)
        refuse("out_dir", "cannot copy " + delay.weights_path() + " into " + dir + " (" + ec.message() + ")");
    nn::save_module(net.ptr(), (fsys::path(dir) / position_estimator::weights_file).string());
    result.bundle.directory = dir;

    // The test frames at each SNR: noise drawn once per frame and scaled (the same frames and
    // noise at every SNR), through the loaded bundle, beside beamforming and the bound.
    const position_estimator loaded(model_bundle::load(dir), s.threads > 0 ? s.threads : 1);
    const beamforming_angle_estimator beam(array, 0.0, lambda);
    const bundle_decoder one_antenna(model_bundle::load(dir), s.threads > 0 ? s.threads : 1);
    auto test_gen = at::make_generator<at::CPUGeneratorImpl>(s.seed + 41);
    const auto unit_noise = training::add_noise(torch::zeros_like(test.obs), torch::ones({ n_test }), test_gen);
    nlohmann::json by_snr = nlohmann::json::array();
    for (double snr : s.eval_snr_db) {
        const double sigma2 = channel_model::noise_variance(snr);
        const auto noisy = (test.obs + unit_noise * float(std::sqrt(sigma2))).contiguous();
        const auto* obs = reinterpret_cast<const gr_complex*>(noisy.data_ptr<float>());
        std::vector<double> learned, network, bf, delay_learned, delay_one(static_cast<size_t>(n_test));
        constexpr int chunk = 256;
        std::vector<gr_complex> first_element(size_t(chunk) * np);
        for (int64_t a = 0; a < n_test; a += chunk) {
            const int b = int(std::min<int64_t>(chunk, n_test - a));
            const gr_complex* y = obs + size_t(a) * k * np;
            for (const auto& e : loaded.estimate(y, b)) {
                learned.push_back(e.azimuth_rad);
                delay_learned.push_back(e.delay_index);
            }
            const auto net_only = loaded.estimate_azimuth(y, b, false);
            network.insert(network.end(), net_only.begin(), net_only.end());
            for (int f = 0; f < b; ++f) {
                bf.push_back(beam.estimate(y + size_t(f) * k * np, np)[0]);
                std::copy(y + size_t(f) * k * np, y + size_t(f) * k * np + np, first_element.begin() + size_t(f) * np);
            }
            const auto one = one_antenna.estimate_delay_index(first_element.data(), b);
            std::copy(one.begin(), one.end(), delay_one.begin() + a);
        }
        double crb = 0.0;
        int bounded = 0;
        for (int64_t f = 0; f < n_test; ++f)
            if (std::isfinite(test.gain2[size_t(f)]) && test.gain2[size_t(f)] > 0.0) {
                crb += angle_crb_rad2(array, test.azimuth[size_t(f)], 0.0, lambda, np * test.gain2[size_t(f)] / sigma2);
                ++bounded;
            }
        nlohmann::json row = { { "snr_db", snr },
                               { "frames", n_test },
                               { "rmse_azimuth_rad", rms(learned, test.azimuth) },
                               { "rmse_azimuth_network_rad", rms(network, test.azimuth) },
                               { "rmse_azimuth_beamforming_rad", rms(bf, test.azimuth) },
                               { "mae_index", mean_abs(delay_learned, test.delay_index) },
                               { "median_abs_error_index", median_abs(delay_learned, test.delay_index) },
                               { "mae_index_one_element", mean_abs(delay_one, test.delay_index) } };
        if (bounded == n_test)
            row["crb_azimuth_rad"] = std::sqrt(crb / double(bounded));
        std::ostringstream line;
        line << "test " << snr << " dB: azimuth RMSE " << std::setprecision(4) << row["rmse_azimuth_rad"].get<double>()
             << " rad (network alone " << row["rmse_azimuth_network_rad"].get<double>() << ", beamforming "
             << row["rmse_azimuth_beamforming_rad"].get<double>();
        if (row.contains("crb_azimuth_rad"))
            line << ", CRB " << row["crb_azimuth_rad"].get<double>();
        line << "); delay MAE " << row["mae_index"].get<double>() << " index (one element "
             << row["mae_index_one_element"].get<double>() << ")";
        say(line.str());
        by_snr.push_back(row);
    }
    result.metrics = { { "test_frames", n_test }, { "by_snr", by_snr } };
    result.bundle.position["metrics"] = result.metrics;
    if (scratch) {
        fsys::remove_all(dir, ec);
        result.bundle.directory.clear();
    } else {
        result.bundle.save(dir); // bundle.json again, now with the figures
        say("wrote " + dir);
    }
    result.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return result;
}

} // namespace sems
} // namespace gr
