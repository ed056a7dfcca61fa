// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model (see channel_model.h for the equations). */
#include "core/kernels/complex_kernels.h"
#include "core/common/math_constants.h"
#include "core/kernels/gaussian_generator.h"
#include "core/scene/micro_motion_params.h"
#include "core/kernels/rng.h"
#include "core/channel/scatterer_moments.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {


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

// With a link budget, the strongest target (nearest range, largest RCS) must stay within
// limits::max_link_snr_db on this frame: a frame's values are single-precision floats.
void check_budget_fits(const frame_settings& fs, const scene& sc)
{
    const auto& b = sc.budget();
    if (!b)
        return;
    // Clutter has csr times the targets' power: it counts when stronger than them.
    const double clutter_db = sc.clutter() ? std::max(0.0, sc.clutter()->csr_db) : 0.0;
    auto check = [&](double range_m, double rcs_dbsm, const std::string& what) {
        const double snr = b->snr_db(fs, range_m, rcs_dbsm) + clutter_db;
        if (!(snr <= limits::max_link_snr_db))
            throw std::invalid_argument(what + ": the link budget gives " + std::to_string(snr) + " dB at " +
                                        std::to_string(range_m) + " m and " + std::to_string(rcs_dbsm) +
                                        " dBsm on this frame (clutter above it included), beyond the " +
                                        std::to_string(limits::max_link_snr_db) + " dB a frame holds");
    };
    if (sc.is_random()) {
        for (auto cls : sc.label_classes()) {
            const auto& spec = sc.library().at(static_cast<int>(cls));
            check(spec.range_min_m, spec.rcs_max_dbsm, "random scene, class " + spec.name);
        }
        return;
    }
    const auto& track = sc.track();
    for (size_t i = 0; i < sc.targets().size(); ++i) {
        const auto& t = sc.targets()[i];
        check(track ? std::min(track->range_min_m, t.range_m) : t.range_m, t.rcs_dbsm, "scene target " + std::to_string(i));
    }
}

// A target of a moving fixed scene at time t (the frame's first symbol): R(t) = R_0 − v t
// inside the track; at an end it starts the pass again (restart) or turns around (reflect).
void move_along_track(target_spec& t, const track_spec& track, double t_s)
{
    const double v = t.velocity_mps;
    if (v == 0.0)
        return;
    const double lo = track.range_min_m, hi = track.range_max_m;
    if (track.at_bound == track_bound::restart) {
        const double pass_s = (v > 0.0 ? t.range_m - lo : hi - t.range_m) / std::fabs(v);
        if (!(pass_s > 0.0)) // starts at the end it moves towards: it stays there
            return;
        const double tau = std::fmod(t_s, pass_s);
        t.range_m -= v * tau;
        return;
    }
    // reflect: unfold onto a line of period 2(hi − lo), fold back into [lo, hi]
    const double len = hi - lo;
    double x = std::fmod(t.range_m - lo - v * t_s, 2.0 * len);
    if (x < 0.0)
        x += 2.0 * len;
    const bool returning = x > len;
    t.range_m = lo + (returning ? 2.0 * len - x : x);
    if (returning) { // on the way back: the radial velocity and the heading turn around
        t.velocity_mps = -v;
        if (!std::isnan(t.speed_mps))
            t.heading_rad += M_PI;
    }
}

// Clutter scatterer k's azimuth as an array sees it: a fixed scatterer's given azimuth (0 when
// none is given), a drawn one's uniform on [−π/2, π/2).
double clutter_azimuth(const clutter_spec& c, size_t k, rng& g)
{
    if (!c.ranges_m.empty())
        return c.azimuths_rad.empty() ? 0.0 : c.azimuths_rad[k];
    return g.uniform(-0.5 * M_PI, 0.5 * M_PI);
}

// One random target: class, range, speed, heading, micro-motion and extra paths, drawn in
// this order from g (the paper scenes' frames depend on it).
void draw_target(target_spec& t,
                 const random_spec& r,
                 const std::vector<target_class>& classes,
                 const class_library& lib,
                 bool budget,
                 rng& g)
{
    t.cls = classes[g.below(classes.size())];
    const auto& spec = lib.at(static_cast<int>(t.cls));
    t.range_m = g.uniform(spec.range_min_m, spec.range_max_m);
    t.velocity_mps = g.uniform(spec.speed_min_mps, spec.speed_max_mps);
    t.power = target_spec{}.power;
    t.md.reset();
    t.motion.reset();
    t.speed_mps = t.velocity_mps;
    t.heading_rad = 0.0;
    // "any" heading: radial velocity speed·cos θ, θ ~ U[0, 2π). Drawn after the speed,
    // and only for this heading, so approaching scenes keep their exact frames.
    if (r.heading == heading_kind::any) {
        t.heading_rad = g.uniform(0.0, two_pi);
        t.velocity_mps *= std::cos(t.heading_rad);
    }
    if (r.micro_doppler && spec.motion) {
        if (spec.motion->model == "sinusoid")
            t.md = detail::draw_sinusoid(*spec.motion, &g, t.speed_mps);
        else
            t.motion = detail::draw_motion(*spec.motion, &g, t.speed_mps);
    }
    t.paths.clear();
    t.paths.push_back({ 0.0, 1.0 });
    for (int k = 1; k < r.paths_per_target; ++k)
        t.paths.push_back({ g.uniform(r.excess_range_min_m, r.excess_range_max_m),
                            db_to_linear(-k * r.path_power_decay_db) });
    // Last, and only with a link budget, so scenes without one keep their exact frames.
    t.rcs_dbsm = budget ? g.uniform(spec.rcs_min_dbsm, spec.rcs_max_dbsm) : target_spec{}.rcs_dbsm;
    // The azimuth after everything else, and drawn only for an interval, for the same reason:
    // the class's own interval where its library gives one, else the scene's.
    const double az_lo = spec.has_azimuth() ? spec.azimuth_min_rad : r.azimuth_min_rad;
    const double az_hi = spec.has_azimuth() ? spec.azimuth_max_rad : r.azimuth_max_rad;
    t.azimuth_rad = az_lo < az_hi ? g.uniform(az_lo, az_hi) : az_lo;
    // The elevation after the azimuth, drawn only for an interval (the class's, else the
    // scene's); the radial velocity is the ground-plane velocity's projection on the line of sight.
    const double el_lo = spec.has_elevation() ? spec.elevation_min_rad : r.elevation_min_rad;
    const double el_hi = spec.has_elevation() ? spec.elevation_max_rad : r.elevation_max_rad;
    t.elevation_rad = el_lo < el_hi ? g.uniform(el_lo, el_hi) : el_lo;
    if (t.elevation_rad != 0.0)
        t.velocity_mps *= std::cos(t.elevation_rad);
}

} // namespace

// --- frame_channel --------------------------------------------------------------

// The frame's scatterer bodies as every element of an array shares them (array_channel): each
// body's model and its snapshot with cross-range offsets, taken by the first element's update.
struct body_share {
    bool cross_range = false; // some element is off the origin: the snapshots carry cross-range offsets
    std::vector<detail::body_model> models;
    std::vector<detail::body_snapshot> snaps;
    std::vector<char> taken; // per body: its snapshot is this frame's
};

struct frame_channel::scratch {
    body_share* shared = nullptr;                     // an array_channel's shared bodies, or none
    detail::body_snapshot steered;                    // a snapshot as this element sees it
    std::vector<detail::expansion_plan> plans;        // per body
    std::vector<size_t> g_offset;                     // per body: its moments in g
    std::vector<std::complex<double>> g;              // per body: N x S x (P+1), scaled by δk_max^p
    std::vector<double> dk_scale;                     // per body: δk_max of its sub-bands
    std::vector<detail::body_model> models;           // per body, kept while its parameters stay
    detail::body_snapshot snap;
    std::vector<double> times;                        // the frame's symbol times
    struct block {                                    // a scatterer body's path in the rows
        int row;                                      // its first row: its delay phasor e, then u (twice)
        detail::expansion_plan plan;
    };
    std::vector<block> blocks; // after the point paths' rows: evaluated by Horner's rule in δk
    int point_rows = 0;        // rows 0 .. point_rows − 1: one per point path, summed as they are
};


frame_channel::frame_channel(const frame_settings& fs, const std::vector<channel_path>& paths, uint64_t first_symbol)
    : d_fs(fs), d_n(fs.n_symbols), d_m(fs.n_subcarriers), d_l(0), d_scratch(std::make_unique<scratch>())
{
    update(paths, nullptr, first_symbol);
}

frame_channel::frame_channel(const frame_settings& fs, const frame_realization& r, uint64_t first_symbol)
    : d_fs(fs), d_n(fs.n_symbols), d_m(fs.n_subcarriers), d_l(0), d_scratch(std::make_unique<scratch>())
{
    update(r.paths, &r.bodies, r.clock_symbol.value_or(first_symbol));
}

frame_channel::frame_channel(const frame_settings& fs, const frame_realization& r, uint64_t first_symbol,
                             const array_element& element)
    : d_fs(fs), d_element(element), d_n(fs.n_symbols), d_m(fs.n_subcarriers), d_l(0),
      d_scratch(std::make_unique<scratch>())
{
    update(r.paths, &r.bodies, r.clock_symbol.value_or(first_symbol));
}

frame_channel::~frame_channel() = default;
frame_channel::frame_channel(frame_channel&&) noexcept = default;
frame_channel& frame_channel::operator=(frame_channel&&) noexcept = default;
frame_channel::frame_channel(const frame_channel& o)
    : d_fs(o.d_fs),
      d_element(o.d_element),
      d_n(o.d_n),
      d_m(o.d_m),
      d_l(o.d_l),
      d_slow(o.d_slow),
      d_delay(o.d_delay),
      d_delay_key(o.d_delay_key),
      d_scratch(std::make_unique<scratch>()) // working memory, but for the rows' layout
{
    d_scratch->blocks = o.d_scratch->blocks;
    d_scratch->point_rows = o.d_scratch->point_rows;
}
frame_channel& frame_channel::operator=(const frame_channel& o)
{
    if (this != &o)
        *this = frame_channel(o);
    return *this;
}

void frame_channel::update(const std::vector<channel_path>& paths, uint64_t first_symbol)
{
    update(paths, nullptr, first_symbol);
}

void frame_channel::update(const frame_realization& r, uint64_t first_symbol)
{
    update(r.paths, &r.bodies, r.clock_symbol.value_or(first_symbol));
}

void frame_channel::update(const std::vector<channel_path>& paths,
                           const std::vector<scatterer_body>* bodies,
                           uint64_t first_symbol)
{
    const frame_settings& fs = d_fs;
    const double T = fs.symbol_interval_s;
    auto& sc = *d_scratch;

    // Scatterer bodies: each one's expansion (scatterer_moments.h) and its moments per symbol.
    const size_t n_bodies = bodies ? bodies->size() : 0;
    sc.plans.resize(n_bodies);
    sc.g_offset.resize(n_bodies);
    sc.dk_scale.resize(n_bodies);
    size_t g_size = 0;
    const double dk = 4.0 * M_PI * fs.subcarrier_spacing_hz() / speed_of_light_mps;
    // An array element (steering.h) turns each path's gain by its steering phasor and pattern
    // and moves its delay by the plane wave's delay at the element; a body's scatterers each from
    // their own direction. The origin skips this, so a single antenna's factors are today's, bit
    // for bit.
    const bool steered = !d_element.is_origin();
    std::vector<detail::body_model>& models = sc.shared ? sc.shared->models : sc.models;
    if (sc.shared && sc.shared->taken.size() < n_bodies) {
        sc.shared->taken.resize(n_bodies, 0);
        sc.shared->snaps.resize(n_bodies);
    }
    for (size_t b = 0; b < n_bodies; ++b) {
        // The frame's scatterers, every symbol in one pass (once per frame for all of an array's
        // elements); the expansion's order from their own amplitudes and reaches (the same
        // bound); per symbol the body's terms G_p δk_max^p.
        detail::body_snapshot* snap = sc.shared ? &sc.shared->snaps[b] : &sc.snap;
        if (!sc.shared || !sc.shared->taken[b]) {
            if (models.size() > n_bodies)
                models.erase(models.begin() + n_bodies, models.end());
            // A fixed scene's bodies are the same every frame: set up once (a walker's takes ~0.1 ms).
            if (b >= models.size())
                models.emplace_back((*bodies)[b], fs);
            else if (!detail::same_body(models[b].body(), (*bodies)[b]))
                models[b] = detail::body_model((*bodies)[b], fs);
            sc.times.resize(size_t(d_n));
            for (int n = 0; n < d_n; ++n)
                sc.times[n] = static_cast<double>(first_symbol + static_cast<uint64_t>(n)) * T;
            models[b].snapshots(sc.times.data(), d_n, *snap, steered || (sc.shared && sc.shared->cross_range));
            if (sc.shared)
                sc.shared->taken[b] = 1;
        }
        if (steered) { // where the body is: its first path's range and direction
            const channel_path* at = nullptr;
            for (const auto& p : paths)
                if (p.body == static_cast<int>(b)) {
                    at = &p;
                    break;
                }
            if (at) {
                const auto g = detail::make_body_steering(0.5 * speed_of_light_mps * at->delay_s, at->azimuth_rad,
                                                          at->elevation_rad, d_element);
                detail::steer_snapshot(*snap, g, sc.steered);
                snap = &sc.steered;
            }
        }
        const auto plan = detail::plan_expansion(fs, *snap);
        sc.plans[b] = plan;
        sc.g_offset[b] = g_size;
        sc.dk_scale[b] = detail::band_scale(fs, plan);
        g_size += size_t(d_n) * plan.terms();
        sc.g.resize(g_size);
        detail::snapshot_terms(*snap, plan, fs, sc.g.data() + sc.g_offset[b]);
    }

    // Rows: one per point path, then plan.terms() per scatterer-body path (its terms side by
    // side in d_slow; in d_delay its delay phasor and the subcarriers' (δk/δk_max)).
    int rows = 0, body_rows = 0;
    for (const auto& p : paths) {
        if (p.body < 0) {
            ++rows;
            continue;
        }
        if (static_cast<size_t>(p.body) >= n_bodies)
            throw std::invalid_argument("frame_channel: a path refers to scatterer body " + std::to_string(p.body) +
                                        " but the frame has " + std::to_string(n_bodies));
        body_rows += sc.plans[p.body].terms();
    }
    sc.point_rows = rows;
    sc.blocks.clear();
    // resize() keeps the capacity: once grown to the scene's row count, no allocation.
    d_l = rows + body_rows;
    d_slow.resize(size_t(d_l) * d_n);
    d_delay.resize(size_t(d_l) * d_m);
    // A row is recomputed only when its key (path delay, term) changed: a fixed scene's
    // delay rows are the same every frame (the same values, not an approximation of them).
    d_delay_key.resize(size_t(d_l) * 3, std::numeric_limits<double>::quiet_NaN());
    const double md_scale = 4.0 * M_PI / fs.wavelength_m();
    const double lambda = fs.wavelength_m();
    int row = 0, body_row = rows;
    for (const auto& path : paths) {
        const bool has_md = path.md_rate_hz > 0.0 && path.md_amplitude_m > 0.0;
        // At an element, the path as it arrives there (its scatterers' own directions are in
        // the body's snapshot, above).
        const channel_path p = steered ? detail::steered_path(path, d_element, lambda) : path;
        const std::complex<double> gain = p.gain;
        const double delay_s = p.delay_s;
        // Doppler and delay phasors by recurrence in double precision: two sin/cos per path
        // instead of N + M. The frame's first phase is anchored to the absolute symbol
        // index, so the rounding of 32 or 64 products (~1e-14) never accumulates across frames.
        std::complex<double> v = gain * doppler_phasor(static_cast<double>(first_symbol), p.doppler_hz, T);
        const std::complex<double> doppler_step = doppler_phasor(1.0, p.doppler_hz, T);
        if (p.body >= 0) {
            const auto& plan = sc.plans[p.body];
            const int terms = plan.terms();
            for (int n = 0; n < d_n; ++n, v *= doppler_step) {
                const std::complex<double>* g = sc.g.data() + sc.g_offset[p.body] + size_t(n) * terms;
                for (int k = 0; k < terms; ++k)
                    d_slow[size_t(n) * d_l + body_row + k] = gr_complex(v * g[k]);
            }
            fill_body_rows(body_row, delay_s, plan, sc.dk_scale[p.body], dk);
            sc.blocks.push_back({ body_row, plan });
            body_row += terms;
            continue;
        }
        for (int n = 0; n < d_n; ++n, v *= doppler_step) {
            std::complex<double> slow = v;
            if (has_md) { // only paths that have micro-Doppler pay for its sine
                const double s = static_cast<double>(first_symbol + static_cast<uint64_t>(n));
                const double wt = p.md_rate_hz * T * s;
                const double arg = two_pi * (wt - std::floor(wt)) + p.md_phase_rad;
                const double phase = md_scale * p.md_amplitude_m * std::sin(arg);
                slow *= std::complex<double>(std::cos(phase), std::sin(phase));
            }
            d_slow[size_t(n) * d_l + row] = gr_complex(slow);
        }
        fill_delay_row(row, delay_s);
        ++row;
    }
}

array_channel::array_channel(const frame_settings& fs, const std::vector<array_element>& elements)
    : d_share(std::make_unique<body_share>())
{
    if (elements.empty())
        throw std::invalid_argument("array_channel: an array needs at least one stream, got none");
    d_channels.reserve(elements.size());
    for (const auto& e : elements) {
        d_share->cross_range = d_share->cross_range || !e.is_origin();
        d_channels.emplace_back(fs, std::vector<channel_path>{}, 0);
        d_channels.back().d_element = e;
        d_channels.back().d_scratch->shared = d_share.get();
    }
}

array_channel::~array_channel() = default;
array_channel::array_channel(array_channel&&) noexcept = default;
array_channel& array_channel::operator=(array_channel&&) noexcept = default;

void array_channel::update(const frame_realization& r, uint64_t first_symbol)
{
    std::fill(d_share->taken.begin(), d_share->taken.end(), 0);
    for (auto& c : d_channels)
        c.update(r, first_symbol);
}

const frame_channel& array_channel::element(int k) const
{
    if (k < 0 || k >= n_elements())
        throw std::invalid_argument("array_channel: stream " + std::to_string(k) + " is beyond the array's " +
                                std::to_string(n_elements()));
    return d_channels[size_t(k)];
}

void frame_channel::fill_delay_row(int row, double delay_s)
{
    // exp(-j2π m Δf τ), m < M, by recurrence in double.
    double* key = d_delay_key.data() + size_t(row) * 3;
    if (key[0] == delay_s && key[1] == -1.0)
        return;
    key[0] = delay_s;
    key[1] = -1.0;
    key[2] = 0.0;
    std::complex<double> d(1.0, 0.0);
    const std::complex<double> delay_step = delay_phasor(1.0, d_fs.delay_index(delay_s), d_m);
    for (int m = 0; m < d_m; ++m, d *= delay_step)
        d_delay[size_t(row) * d_m + m] = gr_complex(d);
}

void frame_channel::fill_body_rows(int row, double delay_s, const detail::expansion_plan& plan, double dk_scale, double dk)
{
    // Row `row`: the path's delay phasor; row + 1 (when the plan has more than one term): each
    // subcarrier's u = δk_m/δk_max ∈ [−1, 1] in its sub-band, twice (the Horner kernel's layout).
    fill_delay_row(row, delay_s);
    if (plan.terms() < 2)
        return;
    double* key = d_delay_key.data() + size_t(row + 1) * 3;
    const double plan_key = 1000.0 * plan.order + 1e6 * plan.band_len;
    if (key[0] == -2.0 && key[1] == plan_key && key[2] == dk_scale)
        return;
    key[0] = -2.0;
    key[1] = plan_key;
    key[2] = dk_scale;
    auto* u2 = reinterpret_cast<float*>(d_delay.data() + size_t(row + 1) * d_m);
    for (int band = 0; band < plan.sub_bands; ++band) {
        const int m0 = band * plan.band_len;
        const int len = std::min(plan.band_len, d_m - m0);
        const double centre = m0 + 0.5 * (len - 1);
        for (int m = m0; m < m0 + len; ++m)
            u2[2 * m] = u2[2 * m + 1] = static_cast<float>((m - centre) * dk / dk_scale);
    }
}

namespace {

// Row n of H without the scatterer bodies from `count` on: the point paths' rows, then each
// body's polynomial on its sub-bands (Σ_p δk_m^p G_p in u = δk_m/δk_max, times its delay).
// `Block` is frame_channel's scratch::block (deduced: the type is private).
template <class Block>
void partial_row(gr_complex* h, const gr_complex* delay, int m, const gr_complex* slow, int point_rows,
                 const Block* blocks, size_t count)
{
    detail::row_sum(h, delay, m, slow, point_rows, m);
    for (size_t i = 0; i < count; ++i) {
        const Block& b = blocks[i];
        const gr_complex* e = delay + size_t(b.row) * m;
        const auto* u2 = reinterpret_cast<const float*>(e + m); // unused when P = 0
        const int terms = b.plan.order + 1;
        for (int band = 0; band < b.plan.sub_bands; ++band) {
            const int m0 = band * b.plan.band_len;
            detail::add_horner(h, e, u2, slow + b.row + band * terms, b.plan.order, m0, std::min(m0 + b.plan.band_len, m));
        }
    }
}

} // namespace

void frame_channel::row(int n, gr_complex* h) const
{
    const auto& sc = *d_scratch;
    partial_row(h, d_delay.data(), d_m, d_slow.data() + size_t(n) * d_l, sc.point_rows, sc.blocks.data(),
                sc.blocks.size());
}

void frame_channel::apply_row(int n, const gr_complex* x, gr_complex* y) const
{
    if (d_scratch->blocks.empty()) {
        // One pass: each subcarrier's H[n,m] summed over the paths in registers, times x.
        detail::apply_row_sum(y, x, d_delay.data(), d_m, d_slow.data() + size_t(n) * d_l, d_l, d_m);
        return;
    }
    thread_local std::vector<gr_complex> h; // per thread: apply_row stays const and reentrant
    const auto& blocks = d_scratch->blocks;
    const auto& last = blocks.back();
    if (last.plan.sub_bands > 1) {
        h.resize(size_t(d_m));
        row(n, h.data());
        detail::multiply(y, x, h.data(), d_m);
        return;
    }
    // The last body's path has one sub-band, the whole row: the rest of the row first (point
    // paths, other bodies; nothing at all when it is the only path), then its polynomial, the
    // sum and the product with x in one pass, with the same operations as row() and multiply()
    // (one pass over the row instead of three for a target alone).
    const gr_complex* rest = nullptr;
    if (d_scratch->point_rows > 0 || blocks.size() > 1) {
        h.resize(size_t(d_m));
        partial_row(h.data(), d_delay.data(), d_m, d_slow.data() + size_t(n) * d_l, d_scratch->point_rows,
                    blocks.data(), blocks.size() - 1);
        rest = h.data();
    }
    const gr_complex* e = d_delay.data() + size_t(last.row) * d_m;
    const auto* u2 = reinterpret_cast<const float*>(e + d_m); // unused when P = 0
    detail::apply_horner(y, x, rest, e, u2, d_slow.data() + size_t(n) * d_l + last.row, last.plan.order, d_m);
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
    std::vector<target_class> every_class; // a random scene without a class list draws from these
    const std::vector<target_class>& all_classes(const class_library& lib)
    {
        if (every_class.size() != static_cast<size_t>(lib.size())) {
            every_class.clear();
            for (int i = 0; i < lib.size(); ++i)
                every_class.push_back(static_cast<target_class>(i));
        }
        return every_class;
    }
    double noise_snr_db = std::numeric_limits<double>::quiet_NaN(); // add_noise's last SNR
    float noise_sigma = 0.0f;                                          // and its σ

    // A tracked random scene's current track: its targets at its first frame, its clutter
    // ranges, its paths' current gains, and its own generator (seeded from the seed and the
    // track index: any track is drawn without the ones before it).
    struct track_state {
        bool active = false;
        uint64_t index = 0;
        int length = 0;
        int next = 0; // its next frame
        rng draws;
        std::vector<target_spec> start;
        std::vector<double> clutter_ranges;
        std::vector<double> clutter_azimuths; // with an array: drawn with the track, kept over it
        std::vector<std::complex<double>> gains;
    } track;
    uint64_t seed;

    explicit rngs(uint64_t s) : draws(s), noise(s ^ 0x6e6f697365ULL), seed(s) {}
    void reseed(uint64_t s)
    {
        draws.reseed(s);
        noise.reseed(s ^ 0x6e6f697365ULL);
        seed = s;
        track.active = false;
    }
};

channel_model::channel_model(const frame_settings& fs, const scene& sc, uint64_t seed)
    : d_fs(fs), d_scene(sc), d_rng(std::make_unique<rngs>(seed))
{
    d_fs.validate();
    d_scene.validate();
    d_elements = d_scene.array() ? virtual_elements(*d_scene.array()) : std::vector<array_element>(1);
    if (d_elements.size() > static_cast<size_t>(limits::max_array_elements))
        throw std::invalid_argument("scene's array: " + std::to_string(d_scene.array()->n_receive()) + " receive × " +
                                    std::to_string(d_scene.array()->n_transmit()) + " transmit elements give " +
                                    std::to_string(d_elements.size()) + " streams, more than the " +
                                    std::to_string(limits::max_array_elements) + " limits.h allows");
    const auto& c = d_scene.clutter();
    if (c) {
        if (c->ranges_m.empty())
            check_inside_frame(d_fs, c->range_max_m, 0.0, "clutter");
        for (double r : c->ranges_m)
            check_inside_frame(d_fs, r, 0.0, "clutter");
    }
    // The sinusoid is narrowband and must stay unambiguous as a whole (the paper's model); a
    // scatterer model's bulk Doppler must, its micro-motion may fold as in a real receiver.
    const auto& lib = d_scene.library();
    if (const auto& r = d_scene.random_settings()) {
        for (auto cls : d_scene.label_classes()) {
            const auto& spec = lib.at(static_cast<int>(cls));
            const bool sinusoid = r->micro_doppler && spec.motion_model() == "sinusoid";
            const double max_range = spec.range_max_m + (r->paths_per_target > 1 ? r->excess_range_max_m : 0.0) +
                                     (r->micro_doppler ? spec.max_extent_m() : 0.0);
            const double peak = 2.0 / d_fs.wavelength_m() *
                                (spec.speed_max_mps + (sinusoid ? spec.max_sinusoid_speed_mps() : 0.0));
            check_inside_frame(d_fs, max_range, peak, "random scene, class " + spec.name + " (class library " + lib.name() + ")");
        }
    } else {
        const auto& targets = d_scene.targets();
        const auto& track = d_scene.track();
        for (size_t i = 0; i < targets.size(); ++i) {
            const auto& t = targets[i];
            double max_excess = 0.0;
            for (const auto& p : t.paths)
                max_excess = std::max(max_excess, p.excess_range_m);
            if (t.motion)
                max_excess += micro_motion_extent_m(*t.motion);
            const double peak = peak_doppler_hz(
                d_fs, t.velocity_mps, t.md ? t.md->rate_hz : 0.0, t.md ? t.md->amplitude_m : 0.0);
            check_inside_frame(d_fs, (track ? track->range_max_m : t.range_m) + max_excess, peak,
                               "scene target " + std::to_string(i));
        }
    }
    check_budget_fits(d_fs, d_scene);
}

channel_model::~channel_model() = default;
channel_model::channel_model(channel_model&&) noexcept = default;
channel_model& channel_model::operator=(channel_model&&) noexcept = default;

void channel_model::reseed(uint64_t seed) { d_rng->reseed(seed); }

namespace {
// Track k's generator seed: splitmix64 at step k of a stream started from the seed, so
// neighbouring seeds and tracks give unrelated streams (rng::reseed expands it again).
uint64_t track_seed(uint64_t seed, uint64_t k)
{
    uint64_t x = (seed ^ 0x747261636b73ULL) + 0x9e3779b97f4a7c15ULL * k;
    return rng::splitmix64(x);
}

// Frames a target stays inside [lo, hi] moving at radial velocity v from R_0, at most `cap`:
// the largest L with R_0 − v·j·Δ inside for every j < L (Δ: one frame's duration), checked
// with the very expression the frames use.
int frames_inside(double r0, double v, double frame_s, double lo, double hi, int cap)
{
    if (v == 0.0)
        return cap;
    const double room = v > 0.0 ? r0 - lo : hi - r0;
    const double guess = std::floor(room / (std::fabs(v) * frame_s)) + 1.0;
    int len = guess >= double(cap) ? cap : std::max(1, static_cast<int>(guess));
    auto inside = [&](int j) {
        const double r = r0 - v * (static_cast<double>(j) * frame_s);
        return r >= lo && r <= hi;
    };
    while (len > 1 && !inside(len - 1))
        --len;
    while (len < cap && inside(len))
        ++len;
    return len;
}
// A tracked body moved d = s·t_s along a straight line in the ground plane from its first frame
// (track_motion::straight; the formulas are track_draw_spec's): its height kept, its range,
// elevation, azimuth and heading to the line of sight turned with its position, its radial
// velocity the projection of its speed.
void move_straight(target_spec& t, double t_s)
{
    const double d = t.speed_mps * t_s;
    const double rho0 = t.range_m * std::cos(t.elevation_rad);
    const double z = t.range_m * std::sin(t.elevation_rad);
    const double along = rho0 - d * std::cos(t.heading_rad); // along the first line of sight, from the radar
    const double across = d * std::sin(t.heading_rad);       // towards increasing azimuth
    const double rho = std::hypot(along, across);
    const double turn = std::atan2(across, along);
    t.range_m = std::hypot(rho, z);
    t.elevation_rad = std::atan2(z, rho);
    t.azimuth_rad = std::remainder(t.azimuth_rad + turn, two_pi);
    t.heading_rad = std::remainder(t.heading_rad + turn, two_pi);
    t.velocity_mps = t.speed_mps * std::cos(t.heading_rad) * std::cos(t.elevation_rad);
}

// Frames a body moving straight stays inside its range interval and, when it was drawn from
// one, its azimuth interval, at most `cap`: the first L frames with every one inside, checked
// with the very expression the frames use (the range is not monotone: a crossing body comes
// closer, then recedes).
int frames_inside_straight(const target_spec& t0, double frame_s, double lo, double hi, double az_lo, double az_hi, int cap)
{
    if (!(t0.speed_mps > 0.0)) // a still body stays where it is
        return cap;
    const bool bounded_azimuth = az_lo < az_hi;
    int len = 1;
    while (len < cap) {
        target_spec t = t0;
        move_straight(t, static_cast<double>(len) * frame_s);
        if (t.range_m < lo || t.range_m > hi || (bounded_azimuth && (t.azimuth_rad < az_lo || t.azimuth_rad > az_hi)))
            break;
        ++len;
    }
    return len;
}
} // namespace

int channel_model::begin_track(uint64_t track_index)
{
    const auto& r = d_scene.random_settings();
    if (!r || !r->tracks)
        throw std::logic_error("begin_track: the scene draws every frame afresh (it has no random.tracks)");
    const auto& spec = *r->tracks;
    auto& tr = d_rng->track;
    tr.draws.reseed(track_seed(d_rng->seed, track_index));
    rng& g = tr.draws;
    const auto& lib = d_scene.library();
    const auto& classes = r->classes.empty() ? d_rng->all_classes(lib) : r->classes;
    // The targets, in the order and with the draws of a per-frame scene's frame, then the
    // planned length.
    tr.start.resize(static_cast<size_t>(r->n_targets));
    for (auto& t : tr.start)
        draw_target(t, *r, classes, lib, d_scene.budget().has_value(), g);
    tr.clutter_ranges.clear();
    if (const auto& c = d_scene.clutter()) {
        if (c->ranges_m.empty())
            for (int k = 0; k < c->n_paths; ++k)
                tr.clutter_ranges.push_back(g.uniform(c->range_min_m, c->range_max_m));
        else
            tr.clutter_ranges = c->ranges_m;
    }
    const int planned =
        spec.frames_min + static_cast<int>(g.below(static_cast<uint64_t>(spec.frames_max - spec.frames_min) + 1));
    // With an array each clutter scatterer keeps one azimuth over the track (drawn after the
    // length, and only then, so tracks without an array keep their exact frames).
    tr.clutter_azimuths.clear();
    if (d_scene.array() && d_scene.clutter())
        for (size_t k = 0; k < tr.clutter_ranges.size(); ++k)
            tr.clutter_azimuths.push_back(clutter_azimuth(*d_scene.clutter(), k, g));
    const double frame_s = d_fs.n_symbols * d_fs.symbol_interval_s;
    int length = planned;
    for (const auto& t : tr.start) {
        const auto& cs = lib.at(static_cast<int>(t.cls));
        if (spec.motion == track_motion::straight) {
            const double az_lo = cs.has_azimuth() ? cs.azimuth_min_rad : r->azimuth_min_rad;
            const double az_hi = cs.has_azimuth() ? cs.azimuth_max_rad : r->azimuth_max_rad;
            length = std::min(length, frames_inside_straight(t, frame_s, cs.range_min_m, cs.range_max_m, az_lo, az_hi, length));
        } else {
            length = std::min(length, frames_inside(t.range_m, t.velocity_mps, frame_s, cs.range_min_m, cs.range_max_m, planned));
        }
    }
    tr.gains.clear();
    tr.active = true;
    tr.index = track_index;
    tr.length = length;
    tr.next = 0;
    return length;
}

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
    const auto& random = d_scene.random_settings();
    auto& tr = d_rng->track;
    const bool tracked = random && random->tracks;
    if (tracked && (!tr.active || tr.next >= tr.length))
        begin_track(tr.active ? tr.index + 1 : 0);
    // A track's frames draw from its own generator (its gains); other scenes from the model's.
    rng& g = tracked ? tr.draws : d_rng->draws;
    const int in_track = tracked ? tr.next++ : 0;
    out.paths.clear(); // keeps the capacity
    size_t n_bodies = 0; // out.bodies keeps its elements: a body assigned in place keeps its buffers
    const double clutter_share = d_scene.clutter() ? db_to_linear(d_scene.clutter()->csr_db) : 0.0;
    const double target_total = 1.0 / (1.0 + clutter_share);

    // Concrete targets of this frame: a fixed scene's are read in place (a moving one's are
    // copied to their frame's ranges); a random scene's are drawn into reused scratch (path
    // lists keep their capacity).
    const std::vector<target_spec>* targets_of_frame = &d_scene.targets();
    const auto& lib = d_scene.library();
    const bool straight = tracked && random->tracks->motion == track_motion::straight;
    const double track_s = static_cast<double>(in_track) * (d_fs.n_symbols * d_fs.symbol_interval_s);
    if (tracked) { // the track's targets moved on to this frame: R_f = R_0 − v·f·N·T, or along their line
        auto& moved = d_rng->drawn;
        moved = tr.start;
        for (auto& t : moved)
            if (straight)
                move_straight(t, track_s);
            else
                t.range_m -= t.velocity_mps * track_s;
        targets_of_frame = &moved;
    } else if (random) {
        const auto& r = random;
        auto& drawn = d_rng->drawn;
        drawn.resize(static_cast<size_t>(r->n_targets));
        const auto& classes = r->classes.empty() ? d_rng->all_classes(lib) : r->classes;
        for (auto& t : drawn)
            draw_target(t, *r, classes, lib, d_scene.budget().has_value(), g);
        targets_of_frame = &drawn;
    } else if (const auto& track = d_scene.track()) {
        auto& moved = d_rng->drawn;
        moved = d_scene.targets();
        const double t_s = static_cast<double>(frame_index) * d_fs.n_symbols * d_fs.symbol_interval_s;
        for (auto& t : moved)
            move_along_track(t, *track, t_s);
        targets_of_frame = &moved;
    }
    const auto& targets = *targets_of_frame;
    // A target's mean power per resource element: its share of unit power, or with a link
    // budget its SNR from the radar equation at this frame's range (noise at 0 dB is the
    // budget's thermal noise); clutter then has csr times the targets' sum.
    const auto& budget = d_scene.budget();
    double weight_sum = 0.0, budget_sum = 0.0;
    for (const auto& t : targets)
        weight_sum += t.power;
    auto target_power = [&](const target_spec& t) {
        return budget ? db_to_linear(budget->snr_db(d_fs, t.range_m, t.rcs_dbsm)) : target_total * (t.power / weight_sum);
    };
    for (const auto& t : targets) {
        double path_sum = 0.0;
        for (const auto& p : t.paths)
            path_sum += p.power;
        const double doppler = d_fs.doppler_from_velocity(t.velocity_mps);
        int body = -1;
        if (t.motion) {
            const auto sh = target_speed_heading(t);
            body = static_cast<int>(n_bodies);
            if (out.bodies.size() <= n_bodies)
                out.bodies.emplace_back();
            auto& b = out.bodies[n_bodies++];
            b.motion = *t.motion; // the same model's assignment reuses its lists' capacity
            b.speed_mps = sh.first;
            b.heading_rad = sh.second;
            b.elevation_rad = -t.elevation_rad; // the radar seen from the body
        }
        const double power = target_power(t);
        budget_sum += power;
        for (const auto& p : t.paths) {
            channel_path cp;
            cp.body = body;
            cp.delay_s = d_fs.delay_from_range(t.range_m + p.excess_range_m);
            cp.doppler_hz = doppler;
            if (t.md) {
                cp.md_rate_hz = t.md->rate_hz;
                cp.md_amplitude_m = t.md->amplitude_m;
                cp.md_phase_rad = t.md->phase_rad;
            }
            cp.mean_power = power * (p.power / path_sum);
            cp.azimuth_rad = t.azimuth_rad; // a target's extra paths arrive from its own direction
            cp.elevation_rad = t.elevation_rad;
            out.paths.push_back(cp);
        }
    }
    out.bodies.resize(n_bodies);
    if (const auto& c = d_scene.clutter()) {
        // A track's clutter ranges were drawn with its targets; a per-frame scene's are drawn here.
        const auto* fixed_ranges = tracked ? &tr.clutter_ranges : c->ranges_m.empty() ? nullptr : &c->ranges_m;
        const int n = fixed_ranges ? static_cast<int>(fixed_ranges->size()) : c->n_paths;
        for (int k = 0; k < n; ++k) {
            channel_path cp; // static scatterer: zero Doppler, no micro-Doppler
            const double range = fixed_ranges ? (*fixed_ranges)[k] : g.uniform(c->range_min_m, c->range_max_m);
            cp.delay_s = d_fs.delay_from_range(range);
            cp.mean_power = (budget ? clutter_share * budget_sum : 1.0 - target_total) / n;
            // Seen by an array, each scatterer from its own azimuth (a track's kept over it),
            // drawn only then (a scene without an array keeps its exact frames).
            if (d_scene.array())
                cp.azimuth_rad = tracked ? tr.clutter_azimuths[size_t(k)] : clutter_azimuth(*c, size_t(k), g);
            out.paths.push_back(cp);
        }
    }
    const auto coherence = tracked ? random->tracks->gains : gain_coherence::frame;
    if (d_scene.fading() == fading_kind::none) {
        for (auto& p : out.paths)
            p.gain = std::complex<double>(std::sqrt(p.mean_power), 0.0);
    } else if (coherence == gain_coherence::frame || in_track == 0) {
        for (auto& p : out.paths)
            p.gain = g.complex_normal(p.mean_power);
    } else if (coherence == gain_coherence::track) {
        for (size_t l = 0; l < out.paths.size(); ++l)
            out.paths[l].gain = tr.gains[l];
    } else { // Gauss–Markov: stationary CN(0, p_l) with correlation ρ^k between frames k apart
        const double rho = std::exp(-(d_fs.n_symbols * d_fs.symbol_interval_s) / random->tracks->coherence_time_s);
        const double innovation = 1.0 - rho * rho;
        for (size_t l = 0; l < out.paths.size(); ++l) {
            auto& p = out.paths[l];
            p.gain = rho * tr.gains[l] + g.complex_normal(innovation * p.mean_power);
        }
    }
    if (tracked) {
        tr.gains.resize(out.paths.size());
        for (size_t l = 0; l < out.paths.size(); ++l)
            tr.gains[l] = out.paths[l].gain;
    }
    if (straight && in_track > 0) {
        // The carrier phase continues across frames: the range travelled since the track's first
        // frame, less the phase the frame's Doppler phasor gives at its first symbol (its rate
        // changes from frame to frame). Turned after the gains are kept, so the gains' own
        // evolution is untouched. Targets' paths come first, in target order.
        size_t l = 0;
        for (size_t i = 0; i < targets.size(); ++i) {
            const double travelled = 2.0 * (tr.start[i].range_m - targets[i].range_m) / d_fs.wavelength_m(); // cycles
            const double doppler_cycles = d_fs.doppler_from_velocity(targets[i].velocity_mps) * track_s;
            const auto turn = cis_cycles(travelled - doppler_cycles);
            for (size_t k = 0; k < targets[i].paths.size(); ++k)
                out.paths[l++].gain *= turn;
        }
    }

    const auto& toi = targets[d_scene.is_random() ? 0 : d_scene.target_of_interest()];
    auto& truth = out.truth;
    truth.frame = frame_index;
    truth.class_id = static_cast<int>(toi.cls);
    truth.class_name = lib.at(truth.class_id).name;
    truth.micro_motion = toi.motion ? micro_motion_model(*toi.motion) : toi.md ? "sinusoid" : "none";
    truth.range_m = toi.range_m;
    truth.delay_s = d_fs.delay_from_range(toi.range_m);
    truth.delay_index = d_fs.delay_index(truth.delay_s);
    truth.velocity_mps = toi.velocity_mps;
    truth.snr_db = std::numeric_limits<double>::infinity();
    truth.link_snr_db = budget ? budget->snr_db(d_fs, toi.range_m, toi.rcs_dbsm) : std::numeric_limits<double>::quiet_NaN();
    const double no_angle = std::numeric_limits<double>::quiet_NaN();
    truth.azimuth_rad = d_scene.array() ? toi.azimuth_rad : no_angle;
    truth.elevation_rad = d_scene.array() ? toi.elevation_rad : no_angle;
    truth.n_paths = static_cast<int>(out.paths.size());
    if (tracked) {
        truth.track_id = tr.index;
        truth.frame_in_track = static_cast<uint64_t>(in_track);
        out.clock_symbol = static_cast<uint64_t>(in_track) * static_cast<uint64_t>(d_fs.n_symbols);
    } else {
        truth.track_id = random ? frame_index : 0; // a per-frame scene: every frame its own track
        truth.frame_in_track = random ? 0 : frame_index;
        out.clock_symbol.reset();
    }
    out.truth_body = toi.motion ? static_cast<int>(std::count_if(targets.data(), &toi, [](const target_spec& t) { return t.motion.has_value(); })) : -1;
}

frame_channel channel_model::factors(const frame_realization& r, uint64_t first_symbol) const
{
    if (n_elements() > 1) // one stream of several is never taken silently for the scene's channel
        throw std::invalid_argument("channel_model::factors: the scene's array gives " + std::to_string(n_elements()) +
                                    " streams; ask for one by its element index (0 .. " +
                                    std::to_string(n_elements() - 1) + ")");
    return frame_channel(d_fs, r, first_symbol, d_elements.front()); // a lone element may be off the origin
}

frame_channel channel_model::factors(const frame_realization& r, uint64_t first_symbol, int element) const
{
    if (element < 0 || element >= n_elements())
        throw std::invalid_argument("channel_model::factors: element " + std::to_string(element) +
                                    " is beyond the scene's array of " + std::to_string(n_elements()) + " streams");
    return frame_channel(d_fs, r, first_symbol, d_elements[size_t(element)]);
}

std::vector<array_element> virtual_elements(const array_geometry& a)
{
    std::vector<array_element> e;
    for (const auto& o : a.virtual_offsets())
        e.push_back({ o, a.pattern() });
    return e;
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
