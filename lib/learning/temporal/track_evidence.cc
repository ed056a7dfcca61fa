// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what one frame tells a temporal model (see track_evidence.h). */
#include "learning/temporal/track_evidence.h"
#include <algorithm>
#include <complex>
#include <stdexcept>

namespace gr {
namespace sems {
namespace temporal {

acf_plan::acf_plan(const pilot_mask& mask, const std::string& source)
{
    std::vector<int> count(static_cast<size_t>(mask.n_subcarriers()), 0);
    for (const auto& p : mask.positions())
        ++count[static_cast<size_t>(p.m)];
    // The first maximum: the lowest subcarrier among those with the most pilots.
    d_subcarrier = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
    if (count[static_cast<size_t>(d_subcarrier)] < 2)
        throw std::invalid_argument(source + ": no subcarrier holds two pilots, so the pilots have no slow-time "
                                             "autocorrelation (temporal model acf_tcn); give a mask with a "
                                             "subcarrier sampled at two symbols or more");
    const auto& pos = mask.positions();
    for (size_t k = 0; k < pos.size(); ++k)
        if (pos[k].m == d_subcarrier) {
            d_index.push_back(static_cast<int>(k));
            d_symbol.push_back(pos[k].n);
        }
    d_lags = mask.n_symbols() - 1;
}

void acf_plan::compute(const gr_complex* frame, float* out) const
{
    // Double sums: a lag adds up to N − 1 products of numbers of any scale.
    std::vector<std::complex<double>> r(static_cast<size_t>(d_lags), 0.0);
    double power = 0.0;
    const size_t n = d_index.size();
    for (size_t a = 0; a < n; ++a) {
        const std::complex<double> ya(frame[d_index[a]]);
        power += std::norm(ya);
        for (size_t b = 0; b < n; ++b) {
            const int lag = d_symbol[b] - d_symbol[a];
            if (lag > 0)
                r[static_cast<size_t>(lag - 1)] += std::complex<double>(frame[d_index[b]]) * std::conj(ya);
        }
    }
    const double scale = power > 0.0 ? 1.0 / power : 0.0; // an all-zero frame: no shape to read
    for (int k = 0; k < d_lags; ++k) {
        out[k] = static_cast<float>(r[static_cast<size_t>(k)].real() * scale);
        out[d_lags + k] = static_cast<float>(r[static_cast<size_t>(k)].imag() * scale);
    }
}

track_evidence::track_evidence(const bundle_decoder& frames, const nn::temporal_settings& s)
    : d_frames(frames), d_acf(s.kind == "acf_tcn"), d_profile(s.doppler_profile)
{
    if (!d_acf) {
        d_size = frames.evidence_size(d_profile);
        return;
    }
    const auto& b = frames.bundle();
    const int f = frames.super_frames();
    for (int i = 0; i < f; ++i)
        d_plans.emplace_back(b.mask_of_set(i), b.directory + "/" + b.mask_name +
                                                   (f > 1 ? " (set " + std::to_string(i) + ")" : std::string()));
    d_size = d_plans.front().size() + static_cast<int>(b.class_names.size());
}

std::vector<float> track_evidence::operator()(const gr_complex* obs, int batch, const int* sets) const
{
    // The frame decoder first: it refuses a non-finite frame or a bad set for every kind.
    auto frame = d_frames.evidence(obs, batch, d_acf ? false : d_profile, sets);
    if (!d_acf)
        return frame;
    const int np = d_frames.n_pilots();
    const int c = static_cast<int>(d_frames.bundle().class_names.size());
    const int fe = d_frames.evidence_size(false), acf = d_size - c;
    std::vector<float> out(static_cast<size_t>(batch) * d_size);
    for (int i = 0; i < batch; ++i) {
        float* row = out.data() + static_cast<size_t>(i) * d_size;
        d_plans[static_cast<size_t>(sets ? sets[i] : 0)].compute(obs + static_cast<size_t>(i) * np, row);
        const float* logp = frame.data() + static_cast<size_t>(i) * fe + (fe - c);
        std::copy(logp, logp + c, row + acf);
    }
    return out;
}

} // namespace temporal
} // namespace sems
} // namespace gr
