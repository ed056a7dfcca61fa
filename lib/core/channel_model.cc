// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model (see channel_model.h for the equations). */
#include "core/complex_kernels.h"
#include "core/gaussian_generator.h"
#include "core/rng.h"
#include <gnuradio/sems/core/channel_model.h>
#include <gnuradio/sems/core/steering.h>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {

constexpr double two_pi = 2.0 * M_PI;

inline double db_to_linear(double db) { return std::pow(10.0, db / 10.0); }

// Peak instantaneous Doppler of a target: 2/λ · (|v| + 2π f_md A).
double peak_doppler_hz(const frame_settings& fs, double speed, double md_rate, double md_amp)
{
    return 2.0 / fs.wavelength_m() * (std::fabs(speed) + two_pi * md_rate * md_amp);
}

void check_inside_frame(const frame_settings& fs, double range_m, double peak_doppler, const std::string& what)
{
    const double delay = fs.delay_from_range(range_m);
    if (!(delay < fs.max_delay_s()))
        throw std::invalid_argument(what + ": range " + std::to_string(range_m) +
                                    " m is beyond the unambiguous range " + std::to_string(fs.max_range_m()) +
                                    " m of the frame (1/Δf)");
    // Inclusive bound (±1/(2T) is representable); the slack absorbs rounding in 2v/λ.
    if (peak_doppler > fs.max_doppler_hz() * (1.0 + 1e-12))
        throw std::invalid_argument(what + ": peak Doppler " + std::to_string(peak_doppler) +
                                    " Hz exceeds the unambiguous ±" + std::to_string(fs.max_doppler_hz()) +
                                    " Hz of the frame (1/(2T))");
}

} // namespace

// --- frame_channel --------------------------------------------------------------

frame_channel::frame_channel(const frame_settings& fs, const std::vector<channel_path>& paths, uint64_t first_symbol)
    : d_fs(fs), d_n(fs.n_symbols), d_m(fs.n_subcarriers), d_l(0)
{
    update(paths, first_symbol);
}

void frame_channel::update(const std::vector<channel_path>& paths, uint64_t first_symbol)
{
    // resize() keeps the capacity: once grown to the scene's path count, no allocation.
    d_l = static_cast<int>(paths.size());
    d_slow.resize(size_t(d_l) * d_n);
    d_delay.resize(size_t(d_l) * d_m);
    // A row is recomputed only when its path's delay changed: a fixed scene's delay rows
    // are the same every frame (the same values, not an approximation of them).
    d_delay_s.resize(size_t(d_l), std::numeric_limits<double>::quiet_NaN());
    const frame_settings& fs = d_fs;
    const double T = fs.symbol_interval_s;
    const double md_scale = 4.0 * M_PI / fs.wavelength_m();
    for (int l = 0; l < d_l; ++l) {
        const auto& p = paths[l];
        const bool has_md = p.md_rate_hz > 0.0 && p.md_amplitude_m > 0.0;
        // Doppler and delay phasors by recurrence in double precision: two sin/cos per path
        // instead of N + M. The frame's first phase is anchored to the absolute symbol
        // index, so the rounding of 32 or 64 products (~1e-14) never accumulates across frames.
        std::complex<double> v = p.gain * doppler_phasor(static_cast<double>(first_symbol), p.doppler_hz, T);
        const std::complex<double> doppler_step = doppler_phasor(1.0, p.doppler_hz, T);
        for (int n = 0; n < d_n; ++n, v *= doppler_step) {
            std::complex<double> slow = v;
            if (has_md) { // only paths that have micro-Doppler pay for its sine
                const double s = static_cast<double>(first_symbol + static_cast<uint64_t>(n));
                const double wt = p.md_rate_hz * T * s;
                const double arg = two_pi * (wt - std::floor(wt)) + p.md_phase_rad;
                const double phase = md_scale * p.md_amplitude_m * std::sin(arg);
                slow *= std::complex<double>(std::cos(phase), std::sin(phase));
            }
            d_slow[size_t(n) * d_l + l] = gr_complex(slow);
        }
        if (d_delay_s[l] == p.delay_s)
            continue;
        d_delay_s[l] = p.delay_s;
        std::complex<double> d(1.0, 0.0);
        const std::complex<double> delay_step = delay_phasor(1.0, fs.delay_index(p.delay_s), d_m);
        for (int m = 0; m < d_m; ++m, d *= delay_step)
            d_delay[size_t(l) * d_m + m] = gr_complex(d);
    }
}

void frame_channel::row(int n, gr_complex* h) const
{
    detail::row_sum(h, d_delay.data(), d_m, d_slow.data() + size_t(n) * d_l, d_l, d_m);
}

void frame_channel::apply_row(int n, const gr_complex* x, gr_complex* y) const
{
    // One pass: each subcarrier's H[n,m] summed over the paths in registers, times x.
    detail::apply_row_sum(y, x, d_delay.data(), d_m, d_slow.data() + size_t(n) * d_l, d_l, d_m);
}

void frame_channel::fill(gr_complex* grid) const
{
    for (int n = 0; n < d_n; ++n)
        row(n, grid + size_t(n) * d_m);
}

// --- channel_model --------------------------------------------------------------

struct channel_model::rngs {
    rng draws;                // scene parameters and path gains
    gaussian_generator noise; // only noise: the same seed gives the same frames at every SNR
    std::vector<target_spec> drawn; // a random scene's targets of the frame, reused
    double noise_snr_db = std::numeric_limits<double>::quiet_NaN(); // add_noise's last SNR
    float noise_sigma = 0.0f;                                          // and its σ
    explicit rngs(uint64_t seed) : draws(seed), noise(seed ^ 0x6e6f697365ULL) {}
    void reseed(uint64_t seed)
    {
        draws.reseed(seed);
        noise.reseed(seed ^ 0x6e6f697365ULL);
    }
};

channel_model::channel_model(const frame_settings& fs, const scene& sc, uint64_t seed)
    : d_fs(fs), d_scene(sc), d_rng(std::make_unique<rngs>(seed))
{
    d_fs.validate();
    d_scene.validate();
    const auto& c = d_scene.clutter();
    if (c) {
        if (c->ranges_m.empty())
            check_inside_frame(d_fs, c->range_max_m, 0.0, "clutter");
        for (double r : c->ranges_m)
            check_inside_frame(d_fs, r, 0.0, "clutter");
    }
    if (const auto& r = d_scene.random_settings()) {
        for (auto cls : r->classes) {
            const auto& spec = class_info(cls);
            const double md_rate = r->micro_doppler ? spec.md_rate_max_hz : 0.0;
            const double max_range = spec.range_max_m + (r->paths_per_target > 1 ? r->excess_range_max_m : 0.0);
            check_inside_frame(d_fs, max_range,
                               peak_doppler_hz(d_fs, spec.speed_max_mps, md_rate, spec.md_amplitude_m),
                               "random scene, class " + spec.name);
        }
    } else {
        const auto& targets = d_scene.targets();
        for (size_t i = 0; i < targets.size(); ++i) {
            const auto& t = targets[i];
            double max_excess = 0.0;
            for (const auto& p : t.paths)
                max_excess = std::max(max_excess, p.excess_range_m);
            const double peak = peak_doppler_hz(
                d_fs, t.velocity_mps, t.md ? t.md->rate_hz : 0.0, t.md ? t.md->amplitude_m : 0.0);
            check_inside_frame(d_fs, t.range_m + max_excess, peak, "scene target " + std::to_string(i));
        }
    }
}

channel_model::~channel_model() = default;
channel_model::channel_model(channel_model&&) noexcept = default;
channel_model& channel_model::operator=(channel_model&&) noexcept = default;

void channel_model::reseed(uint64_t seed) { d_rng->reseed(seed); }

double channel_model::noise_variance(double snr_db)
{
    if (std::isnan(snr_db))
        throw std::invalid_argument("SNR must not be NaN");
    if (snr_db == std::numeric_limits<double>::infinity())
        return 0.0;
    return std::pow(10.0, -snr_db / 10.0);
}

frame_realization channel_model::draw(uint64_t frame_index)
{
    frame_realization out;
    draw(frame_index, out);
    return out;
}

void channel_model::draw(uint64_t frame_index, frame_realization& out)
{
    rng& g = d_rng->draws;
    out.paths.clear(); // keeps the capacity
    const double clutter_share = d_scene.clutter() ? db_to_linear(d_scene.clutter()->csr_db) : 0.0;
    const double target_total = 1.0 / (1.0 + clutter_share);

    // Concrete targets of this frame: a fixed scene's are read in place; a random
    // scene's are drawn into reused scratch (path lists keep their capacity).
    const std::vector<target_spec>* targets_of_frame = &d_scene.targets();
    if (const auto& r = d_scene.random_settings()) {
        auto& drawn = d_rng->drawn;
        drawn.resize(static_cast<size_t>(r->n_targets));
        for (auto& t : drawn) {
            t.cls = r->classes[g.below(r->classes.size())];
            const auto& spec = class_info(t.cls);
            t.range_m = g.uniform(spec.range_min_m, spec.range_max_m);
            t.velocity_mps = g.uniform(spec.speed_min_mps, spec.speed_max_mps);
            t.power = target_spec{}.power;
            t.md.reset();
            // "any" heading: radial velocity speed·cos θ, θ ~ U[0, 2π). Drawn after the speed,
            // and only for this heading, so approaching scenes keep their exact frames.
            if (r->heading == heading_kind::any)
                t.velocity_mps *= std::cos(g.uniform(0.0, two_pi));
            if (r->micro_doppler && spec.has_micro_doppler())
                t.md = micro_doppler{ g.uniform(spec.md_rate_min_hz, spec.md_rate_max_hz),
                                      spec.md_amplitude_m,
                                      g.uniform(0.0, two_pi) };
            t.paths.clear();
            t.paths.push_back({ 0.0, 1.0 });
            for (int k = 1; k < r->paths_per_target; ++k)
                t.paths.push_back({ g.uniform(r->excess_range_min_m, r->excess_range_max_m),
                                    db_to_linear(-k * r->path_power_decay_db) });
        }
        targets_of_frame = &drawn;
    }
    const auto& targets = *targets_of_frame;

    double weight_sum = 0.0;
    for (const auto& t : targets)
        weight_sum += t.power;
    for (const auto& t : targets) {
        double path_sum = 0.0;
        for (const auto& p : t.paths)
            path_sum += p.power;
        const double doppler = d_fs.doppler_from_velocity(t.velocity_mps);
        for (const auto& p : t.paths) {
            channel_path cp;
            cp.delay_s = d_fs.delay_from_range(t.range_m + p.excess_range_m);
            cp.doppler_hz = doppler;
            if (t.md) {
                cp.md_rate_hz = t.md->rate_hz;
                cp.md_amplitude_m = t.md->amplitude_m;
                cp.md_phase_rad = t.md->phase_rad;
            }
            cp.mean_power = target_total * (t.power / weight_sum) * (p.power / path_sum);
            out.paths.push_back(cp);
        }
    }
    if (const auto& c = d_scene.clutter()) {
        const int n = c->ranges_m.empty() ? c->n_paths : static_cast<int>(c->ranges_m.size());
        for (int k = 0; k < n; ++k) {
            channel_path cp; // static scatterer: zero Doppler, no micro-Doppler
            const double range = c->ranges_m.empty() ? g.uniform(c->range_min_m, c->range_max_m) : c->ranges_m[k];
            cp.delay_s = d_fs.delay_from_range(range);
            cp.mean_power = (1.0 - target_total) / n;
            out.paths.push_back(cp);
        }
    }
    for (auto& p : out.paths)
        p.gain = d_scene.fading() == fading_kind::rayleigh ? g.complex_normal(p.mean_power)
                                                           : std::complex<double>(std::sqrt(p.mean_power), 0.0);

    const auto& toi = targets[d_scene.is_random() ? 0 : d_scene.target_of_interest()];
    auto& truth = out.truth;
    truth.frame = frame_index;
    truth.class_id = static_cast<int>(toi.cls);
    truth.class_name = class_info(toi.cls).name;
    truth.range_m = toi.range_m;
    truth.delay_s = d_fs.delay_from_range(toi.range_m);
    truth.delay_index = d_fs.delay_index(truth.delay_s);
    truth.velocity_mps = toi.velocity_mps;
    truth.snr_db = std::numeric_limits<double>::infinity();
    truth.n_paths = static_cast<int>(out.paths.size());
}

frame_channel channel_model::factors(const frame_realization& r, uint64_t first_symbol) const
{
    return frame_channel(d_fs, r.paths, first_symbol);
}

void channel_model::add_noise(gr_complex* y, size_t count, double snr_db)
{
    auto& st = *d_rng;
    if (!(snr_db == st.noise_snr_db)) { // called per OFDM symbol: σ is computed once per SNR
        const double var = noise_variance(snr_db);
        const float sigma = static_cast<float>(std::sqrt(var));
        if (!std::isfinite(sigma))
            throw std::invalid_argument("add_noise: SNR " + std::to_string(snr_db) +
                                        " dB gives a noise amplitude beyond single precision");
        st.noise_snr_db = snr_db;
        st.noise_sigma = sigma;
    }
    if (st.noise_sigma == 0.0f)
        return; // noiseless: no draw at all
    st.noise.add(y, count, st.noise_sigma);
}

std::vector<frame_truth> channel_model::generate(size_t count, gr_complex* h_out, uint64_t first_frame)
{
    std::vector<frame_truth> truths;
    truths.reserve(count);
    const size_t grid = static_cast<size_t>(d_fs.grid_size());
    for (size_t f = 0; f < count; ++f) {
        const uint64_t frame = first_frame + f;
        auto r = draw(frame);
        factors(r, frame * static_cast<uint64_t>(d_fs.n_symbols)).fill(h_out + f * grid);
        truths.push_back(r.truth);
    }
    return truths;
}

} // namespace sems
} // namespace gr
