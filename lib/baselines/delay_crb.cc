// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: closed-form Cramér–Rao bound on a single path's delay. See delay_crb.h. */
#include "core/common/checks.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <gnuradio/sems/core/array/steering.h>
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {

double delay_crb::spread(const pilot_mask& mask, bool doppler_known)
{
    // Pilot k's Fisher information is weighted by its energy p_k (noise σ²/p_k); for
    // equal power every weight is 1 and the sums are the unweighted ones. Its phase φ_k
    // does not enter: the observation Y/(sqrt(p_k)·s_p·exp(jφ_k)) has circular noise of the
    // same law whatever φ_k (pilot_mask::transmitted_pilot).
    const auto& pos = mask.positions();
    const auto& w = mask.power();
    double k = 0.0, mm = 0.0, nn = 0.0;
    for (size_t i = 0; i < pos.size(); ++i) {
        k += w[i];
        mm += w[i] * pos[i].m;
        nn += w[i] * pos[i].n;
    }
    mm /= k;
    nn /= k;
    double smm = 0.0, snn = 0.0, smn = 0.0;
    for (size_t i = 0; i < pos.size(); ++i) {
        const auto& p = pos[i];
        smm += w[i] * (p.m - mm) * (p.m - mm);
        snn += w[i] * (p.n - nn) * (p.n - nn);
        smn += w[i] * (p.m - mm) * (p.n - nn);
    }
    if (doppler_known || snn <= 0.0)
        return smm;
    return smm - smn * smn / snn;
}

double delay_crb::variance_index(const frame_settings& fs,
                                 const pilot_mask& mask,
                                 double snr_db,
                                 bool doppler_known,
                                 double gain_power)
{
    fs.validate();
    mask.check_frame(fs, "delay CRB");
    if (std::isnan(snr_db))
        throw std::invalid_argument("delay CRB: snr_db is NaN");
    if (!checks::positive(gain_power))
        throw std::invalid_argument("delay CRB: gain_power must be finite and > 0");
    const double s = spread(mask, doppler_known);
    if (!(s > 1e-12))
        throw std::invalid_argument("delay CRB: the pilot pattern has no subcarrier spread (all pilots on one "
                                    "subcarrier, or subcarrier fully tied to symbol): the delay is not identifiable");
    const double sigma2 = channel_model::noise_variance(snr_db);
    const double m = fs.n_subcarriers;
    return m * m * sigma2 / (2.0 * gain_power * 4.0 * M_PI * M_PI * s);
}

double delay_crb::mae_index(const frame_settings& fs,
                            const pilot_mask& mask,
                            double snr_db,
                            bool doppler_known,
                            bool rayleigh,
                            double mean_power)
{
    const double v = variance_index(fs, mask, snr_db, doppler_known, mean_power);
    return rayleigh ? std::sqrt(2.0 * v) : std::sqrt(2.0 * v / M_PI);
}

double delay_crb::multipath_variance_index(const frame_settings& fs,
                                           const pilot_mask& mask,
                                           double snr_db,
                                           const std::vector<crb_path>& paths,
                                           bool doppler_known)
{
    const std::string who = "multipath delay CRB";
    fs.validate();
    mask.check_frame(fs, who);
    if (std::isnan(snr_db))
        throw std::invalid_argument(who + ": snr_db is NaN");
    if (paths.empty())
        throw std::invalid_argument(who + ": no paths");
    for (const auto& p : paths)
        if (!std::isfinite(p.delay_index) || !std::isfinite(p.gain.real()) || !std::isfinite(p.gain.imag()))
            throw std::invalid_argument(who + ": a path delay or gain is not finite");
    if (!(std::norm(paths[0].gain) > 0.0))
        throw std::invalid_argument(who + ": the first path has zero gain: its delay is not identifiable");
    const double sigma2 = channel_model::noise_variance(snr_db);
    if (sigma2 == 0.0)
        return 0.0;
    const auto& pos = mask.positions();
    const int np = mask.size(), l_count = static_cast<int>(paths.size());
    const bool with_doppler = !doppler_known && pos.front().n != pos.back().n;
    const int n_par = 3 * l_count + (with_doppler ? 1 : 0);
    // ν = 0 without loss of generality: b_k multiplies every column and cancels in JᴴJ.
    Eigen::MatrixXcd j(np, n_par);
    for (int k = 0; k < np; ++k) {
        std::complex<double> mu = 0.0;
        for (int l = 0; l < l_count; ++l) {
            const auto a = delay_phasor(pos[k].m, paths[l].delay_index, fs.n_subcarriers);
            mu += paths[l].gain * a;
            j(k, l) = paths[l].gain * std::complex<double>(0.0, -2.0 * M_PI * pos[k].m / fs.n_subcarriers) * a;
            j(k, l_count + 2 * l) = a;
            j(k, l_count + 2 * l + 1) = std::complex<double>(0.0, 1.0) * a;
        }
        if (with_doppler)
            j(k, 3 * l_count) = std::complex<double>(0.0, 2.0 * M_PI * fs.symbol_interval_s * pos[k].n) * mu;
    }
    if (!mask.equal_power()) // pilot k's noise is σ²/p_k: its row weighs sqrt(p_k)
        for (int k = 0; k < np; ++k)
            j.row(k) *= std::sqrt(mask.power()[k]);
    const Eigen::MatrixXd fim = (2.0 / sigma2) * (j.adjoint() * j).real();
    // Singular information (coincident paths, too few pilots): no unbiased estimator, +inf.
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(fim);
    if (lu.rank() < n_par)
        return std::numeric_limits<double>::infinity();
    const Eigen::MatrixXd inv = lu.inverse();
    const double v = inv(0, 0);
    return v > 0.0 && std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
}

} // namespace sems
} // namespace gr
