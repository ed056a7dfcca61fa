// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the learned position decoder of a position bundle (see position_estimator.h). */
#include <gnuradio/sems/learning/array/position_estimator.h>
#include "core/common/json_object.h"
#include "learning/array/angle_network.h"
#include "learning/networks/task_decoder.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/steering.h>
#include <torch/torch.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>
#include <stdexcept>

namespace gr {
namespace sems {

struct position_estimator::impl {
    std::unique_ptr<bundle_decoder> delay;
    std::optional<array_geometry> array;
    nn::angle_settings settings;
    mutable nn::angle_network net{ nullptr }; // forward() is not const; inference changes nothing
    std::unique_ptr<beamforming_angle_estimator> beam;
    double lambda = 0.0;
    int k = 0, np = 0, threads = 0;

    void use_threads() const
    {
        if (threads > 0 && at::get_num_threads() != threads)
            at::set_num_threads(threads);
    }

    void check_finite(const gr_complex* obs, int batch, const char* what) const
    {
        const size_t per = size_t(k) * size_t(np);
        for (int b = 0; b < batch; ++b)
            for (size_t i = 0; i < per; ++i) {
                const gr_complex v = obs[size_t(b) * per + i];
                if (!std::isfinite(v.real()) || !std::isfinite(v.imag()))
                    throw std::invalid_argument(std::string("position_estimator::") + what + ": frame " +
                                                std::to_string(b) + " of the batch of " + std::to_string(batch) +
                                                " holds a non-finite observation (element " + std::to_string(i / np) +
                                                ", pilot " + std::to_string(i % np) +
                                                "): frames with NaN or Inf are not decoded; leave them out of the batch");
            }
    }
};

position_estimator::position_estimator(const model_bundle& bundle, int threads)
    : position_estimator(std::make_unique<bundle_decoder>(bundle, threads), threads)
{
}

position_estimator::position_estimator(std::unique_ptr<bundle_decoder> delay, int threads)
    : d_impl(std::make_unique<impl>())
{
    auto& p = *d_impl;
    p.delay = std::move(delay);
    p.threads = threads;
    const model_bundle& b = p.delay->bundle();
    const std::string source = b.directory + "/" + model_bundle::bundle_file;
    if (b.position.is_null())
        json_read::fail(source, "position", "missing: not a position bundle (sems_train --delay-bundle ... --array ... "
                                            "makes one)");
    if (b.task != task_kind::delay)
        json_read::fail(source, "position", "a position bundle is a delay bundle with an angle decoder");
    if (b.super_frames() != 1)
        json_read::fail(source, "position", "a position bundle's mask spans one frame");
    json_read::object_reader r(b.position, source, "position");
    p.array = array_geometry::from_json(r.require("array"), source + ": position.array", "", true);
    p.settings = nn::angle_settings::from_json(r.require("angle"), source + ": position.angle");
    const std::string weights = r.string("weights_file");
    if (weights.empty() || weights.find('/') != std::string::npos)
        json_read::fail(source, "position.weights_file", "must be a file name in the bundle directory, got \"" + weights + "\"");
    r.allow("training");
    r.allow("metrics");
    r.finish();
    if (p.array->n_transmit() != 1)
        json_read::fail(source, "position.array", "has " + std::to_string(p.array->n_transmit()) +
                                                      " transmit elements; the position decoder takes one");
    p.k = p.array->n_receive();
    p.np = b.mask.size();
    p.lambda = pilot_wavelength_m(b.frame, b.mask);
    p.use_threads();
    p.net = nn::angle_network(*p.array, p.lambda, p.settings);
    nn::load_module(p.net.ptr(), b.directory + "/" + weights);
    p.net->eval();
    angle_search search;
    search.min_rad = p.settings.azimuth_min_rad;
    search.max_rad = p.settings.azimuth_max_rad;
    search.grid = 8; // refine() alone is used: its search grid plays no part
    p.beam = std::make_unique<beamforming_angle_estimator>(*p.array, 0.0, p.lambda, search);
}

position_estimator::~position_estimator() = default;

const model_bundle& position_estimator::bundle() const { return d_impl->delay->bundle(); }
const array_geometry& position_estimator::array() const { return *d_impl->array; }
int position_estimator::n_elements() const { return d_impl->k; }
int position_estimator::n_pilots() const { return d_impl->np; }

std::vector<double> position_estimator::estimate_azimuth(const gr_complex* obs, int batch, bool polish) const
{
    const auto& p = *d_impl;
    if (batch < 1)
        throw std::invalid_argument("position_estimator::estimate_azimuth: batch must be >= 1, got " +
                                    std::to_string(batch));
    p.check_finite(obs, batch, "estimate_azimuth");
    p.use_threads();
    std::vector<double> out(static_cast<size_t>(batch));
    {
        c10::InferenceMode im;
        auto x = torch::from_blob(const_cast<gr_complex*>(obs), { batch, p.k, p.np, 2 }, torch::kFloat);
        const auto az = p.net->forward(x).azimuth.to(torch::kDouble).contiguous();
        std::copy(az.data_ptr<double>(), az.data_ptr<double>() + batch, out.begin());
    }
    const double half = p.settings.polish_steps * p.net->step_rad();
    if (!polish || half <= 0.0)
        return out;
    const size_t per = size_t(p.k) * size_t(p.np);
    for (int b = 0; b < batch; ++b) {
        const double lo = std::max(-M_PI / 2, out[size_t(b)] - half);
        const double hi = std::min(M_PI / 2, out[size_t(b)] + half);
        const double r = p.beam->refine(obs + size_t(b) * per, p.np, lo, hi);
        // Kept only where the spectrum peaks inside the interval (not rising towards an end).
        if (r - lo > 1e-3 * half && hi - r > 1e-3 * half)
            out[size_t(b)] = r;
    }
    return out;
}

std::vector<position_estimate> position_estimator::estimate(const gr_complex* obs, int batch) const
{
    const auto& p = *d_impl;
    const auto azimuth = estimate_azimuth(obs, batch);
    // Each frame's pilots beamformed towards its azimuth: z_p = a(φ̂)ᴴ y_p / ‖a(φ̂)‖².
    const size_t per = size_t(p.k) * size_t(p.np);
    std::vector<gr_complex> beamformed(size_t(batch) * size_t(p.np));
    for (int b = 0; b < batch; ++b)
        beamform_pilots(*p.array, azimuth[size_t(b)], 0.0, p.lambda, obs + size_t(b) * per, p.np,
                        beamformed.data() + size_t(b) * p.np);
    const auto delays = p.delay->estimate_delay(beamformed.data(), batch);
    const frame_settings& fs = p.delay->bundle().frame;
    std::vector<position_estimate> out(static_cast<size_t>(batch));
    for (int b = 0; b < batch; ++b) {
        auto& e = out[size_t(b)];
        e.delay_s = delays[size_t(b)];
        e.delay_index = fs.delay_index(e.delay_s);
        e.range_m = fs.range_from_delay(e.delay_s);
        e.azimuth_rad = azimuth[size_t(b)];
    }
    return out;
}

} // namespace sems
} // namespace gr
