// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a complex product for hot loops (internal to the libraries). */
#ifndef INCLUDED_SEMS_LIB_CORE_COMPLEX_MUL_H
#define INCLUDED_SEMS_LIB_CORE_COMPLEX_MUL_H

#include <complex>

namespace gr {
namespace sems {
namespace detail {

// a·b written out, without the NaN/Inf recovery of std::complex's operator* (__muldc3):
// for operands known to be finite (phasors, their products and powers).
inline std::complex<double> mul(std::complex<double> a, std::complex<double> b)
{
    return { a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real() };
}

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_COMPLEX_MUL_H */
