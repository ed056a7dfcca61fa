// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: co-array MUSIC delay estimator from sparse pilots. See music_delay_estimator.h. */
#include "baselines/pilot_observations.h"
#include <gnuradio/sems/baselines/music_delay_estimator.h>
#include <algorithm>
#include <numeric>
#include <set>

namespace gr {
namespace sems {

using namespace baseline;

struct music_delay_estimator::impl {
    frame_settings fs;
    int np;
    settings s;
    std::vector<double> grid;
    bool full_window;
    int g = 1, l = 1;
    struct pair {
        int i, j, lag; // lag in units of g, 1..L-1
    };
    std::vector<pair> pairs;
    Eigen::MatrixXcd a; // L x Q steering of the virtual array

    Eigen::VectorXd spectrum(const Eigen::VectorXcd& r) const
    {
        // Lag estimates r̂[d], d = 0..L-1 (units of g).
        std::vector<cd> sum(l, cd(0.0, 0.0));
        std::vector<int> cnt(l, 0);
        for (int k = 0; k < np; ++k) {
            sum[0] += std::norm(r[k]);
            ++cnt[0];
        }
        for (const auto& p : pairs) {
            sum[p.lag] += r[p.j] * std::conj(r[p.i]); // m_j > m_i: lag +d
            ++cnt[p.lag];
        }
        // R[a,b] = E[x_a x_b*] for the virtual array x_i ~ exp(-j2π Δf τ i g):
        // x_a x_b* ~ exp(-j2π Δf τ (a-b) g) = r̂[a-b] with r̂[d] ~ exp(-j2π Δf τ d g).
        Eigen::MatrixXcd rr(l, l);
        for (int i = 0; i < l; ++i)
            for (int j = 0; j < l; ++j) {
                const int d = i - j;
                const cd v = sum[std::abs(d)] / double(cnt[std::abs(d)]);
                rr(i, j) = d >= 0 ? v : std::conj(v);
            }
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(rr);
        const Eigen::MatrixXcd en = eig.eigenvectors().leftCols(l - s.n_paths); // ascending
        const Eigen::MatrixXd proj = (en.adjoint() * a).cwiseAbs2();
        Eigen::VectorXd p(a.cols());
        for (Eigen::Index q = 0; q < a.cols(); ++q)
            p[q] = 1.0 / std::max(proj.col(q).sum(), 1e-300);
        return p;
    }
};

music_delay_estimator::music_delay_estimator(const frame_settings& fs, const pilot_mask& mask)
    : music_delay_estimator(fs, mask, settings{})
{
}

music_delay_estimator::music_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s)
    : d_impl(new impl)
{
    const std::string who = "MUSIC delay estimator";
    check_mask(fs, mask, who);
    s.search.validate(fs, who);
    if (s.n_paths < 1)
        throw std::invalid_argument(who + ": n_paths must be >= 1, got " + std::to_string(s.n_paths));
    auto& d = *d_impl;
    d.fs = fs;
    d.np = mask.size();
    d.s = s;
    d.grid = s.search.grid(fs);
    d.full_window = std::abs(d.grid.size() - double(fs.n_subcarriers) * s.search.oversample) < 0.5;

    // The same-symbol difference co-array.
    const auto& pos = mask.positions();
    std::set<int> lags;
    for (int i = 0; i < d.np; ++i)
        for (int j = i + 1; j < d.np && pos[j].n == pos[i].n; ++j)
            lags.insert(pos[j].m - pos[i].m);
    int g = 0;
    for (int lag : lags)
        g = std::gcd(g, lag);
    d.g = std::max(g, 1);
    d.l = 1;
    while (lags.count(d.l * d.g))
        ++d.l;
    if (d.l < s.n_paths + 1)
        throw std::invalid_argument(
            who + ": the pilot pattern's same-symbol co-array has only " + std::to_string(d.l) +
            " contiguous lag(s) (spacing " + std::to_string(d.g) + "); MUSIC with " + std::to_string(s.n_paths) +
            " path(s) needs at least " + std::to_string(s.n_paths + 1) +
            " (put several pilots on the same OFDM symbols)");
    for (int i = 0; i < d.np; ++i)
        for (int j = i + 1; j < d.np && pos[j].n == pos[i].n; ++j) {
            const int lag = pos[j].m - pos[i].m;
            if (lag % d.g == 0 && lag / d.g < d.l)
                d.pairs.push_back({ i, j, lag / d.g });
        }
    d.a.resize(d.l, d.grid.size());
    for (int i = 0; i < d.l; ++i)
        for (size_t q = 0; q < d.grid.size(); ++q)
            d.a(i, q) = delay_phasor(i * d.g, d.grid[q], fs.n_subcarriers);
}

music_delay_estimator::~music_delay_estimator() = default;
music_delay_estimator::music_delay_estimator(music_delay_estimator&&) noexcept = default;

int music_delay_estimator::coarray_spacing() const { return d_impl->g; }
int music_delay_estimator::coarray_length() const { return d_impl->l; }
const std::vector<double>& music_delay_estimator::grid_index() const { return d_impl->grid; }

std::vector<double> music_delay_estimator::pseudo_spectrum(const gr_complex* obs) const
{
    const auto p = d_impl->spectrum(observations(obs, d_impl->np, "MUSIC delay estimator"));
    return std::vector<double>(p.data(), p.data() + p.size());
}

double music_delay_estimator::estimate_index(const gr_complex* obs) const
{
    const auto& d = *d_impl;
    const Eigen::VectorXd p = d.spectrum(observations(obs, d.np, "MUSIC delay estimator"));
    const int n = static_cast<int>(p.size());
    if (d.s.n_paths == 1 || n < 3) {
        Eigen::Index q;
        p.maxCoeff(&q);
        return d.grid[q];
    }
    // The K strongest local maxima; report the earliest.
    std::vector<int> peaks;
    for (int q = 0; q < n; ++q) {
        const bool edge = q == 0 || q == n - 1;
        if (edge && !d.full_window)
            continue;
        const double left = p[(q - 1 + n) % n], right = p[(q + 1) % n];
        if (p[q] > left && p[q] >= right)
            peaks.push_back(q);
    }
    if (peaks.empty()) {
        Eigen::Index q;
        p.maxCoeff(&q);
        return d.grid[q];
    }
    std::sort(peaks.begin(), peaks.end(), [&](int x, int y) { return p[x] > p[y]; });
    peaks.resize(std::min<size_t>(peaks.size(), d.s.n_paths));
    return d.grid[*std::min_element(peaks.begin(), peaks.end())];
}

int music_delay_estimator::n_pilots() const { return d_impl->np; }

double music_delay_estimator::estimate_delay_s(const gr_complex* obs) const
{
    return estimate_index(obs) / d_impl->fs.bandwidth_hz;
}

} // namespace sems
} // namespace gr
