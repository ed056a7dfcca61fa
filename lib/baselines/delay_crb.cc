// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: closed-form Cramér–Rao bound on a single path's delay. See delay_crb.h. */
#include "core/checks.h"
#include <gnuradio/sems/core/channel_model.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

double delay_crb::spread(const pilot_mask& mask, bool doppler_known)
{
    const auto& pos = mask.positions();
    const double k = static_cast<double>(pos.size());
    double mm = 0.0, nn = 0.0;
    for (const auto& p : pos) {
        mm += p.m;
        nn += p.n;
    }
    mm /= k;
    nn /= k;
    double smm = 0.0, snn = 0.0, smn = 0.0;
    for (const auto& p : pos) {
        smm += (p.m - mm) * (p.m - mm);
        snn += (p.n - nn) * (p.n - nn);
        smn += (p.m - mm) * (p.n - nn);
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

double delay_crb::mae_index(const frame_settings& fs, const pilot_mask& mask, double snr_db, bool doppler_known, bool rayleigh)
{
    const double v = variance_index(fs, mask, snr_db, doppler_known, 1.0);
    return rayleigh ? std::sqrt(2.0 * v) : std::sqrt(2.0 * v / M_PI);
}

} // namespace sems
} // namespace gr
