// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: cfo_corrector implementation (see cfo_corrector.h). */
#ifndef INCLUDED_SEMS_CFO_CORRECTOR_IMPL_H
#define INCLUDED_SEMS_CFO_CORRECTOR_IMPL_H

#include <gnuradio/sems/blocks/cfo_corrector.h>
#include <atomic>
#include <complex>

namespace gr {
namespace sems {

class cfo_corrector_impl : public cfo_corrector
{
public:
    cfo_corrector_impl(int m, int cp, int symbols, double forgetting, double snr);

    double cfo() const override { return d_cfo; }
    int timing() const override { return d_timing; }
    uint64_t windows() const override { return d_windows; }

    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    const int d_m, d_cp, d_symbols;
    const double d_forgetting, d_snr;
    std::complex<double> d_avg{ 0.0, 0.0 }; // running e^{−j2πε} estimate (its angle is the offset)
    double d_phase = 0.0;                   // the correction's phase, in turns
    std::atomic<double> d_cfo{ 0.0 };
    std::atomic<int> d_timing{ 0 };
    std::atomic<uint64_t> d_windows{ 0 };
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CFO_CORRECTOR_IMPL_H */
