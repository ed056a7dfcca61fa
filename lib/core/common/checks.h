// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the finite / positive checks every library shares (internal).
 *
 * One definition of "finite", "positive" and "non-negative" for settings and samples:
 * NaN and ±Inf are never positive or non-negative, a complex value is finite when both
 * parts are. The callers keep their own messages (they name the file or parameter and
 * the problem); these only decide.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_CHECKS_H
#define INCLUDED_SEMS_LIB_CORE_CHECKS_H

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace gr {
namespace sems {
namespace checks {

// A value as the messages print it ("%g": 0.1, -100000, 1e-07, inf, nan).
inline std::string text(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

// Neither NaN nor ±Inf.
inline bool finite(double v) { return std::isfinite(v); }
// Both parts finite.
template <typename T>
inline bool finite(const std::complex<T>& z)
{
    return std::isfinite(z.real()) && std::isfinite(z.imag());
}
// Finite and > 0.
inline bool positive(double v) { return std::isfinite(v) && v > 0.0; }
// Finite and >= 0.
inline bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }
// Every element finite (a frame with a NaN/Inf is counted and skipped, never decoded).
template <typename T>
inline bool all_finite(const std::complex<T>* x, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!finite(x[i]))
            return false;
    return true;
}
// Every element finite: the single-precision samples of every stream. Branch-free on the
// exponent bits (all ones = Inf or NaN), so the compiler vectorises it: it runs on every
// OFDM symbol of the emulator and the extractor. (Preferred over the template above.)
inline bool all_finite(const std::complex<float>* x, size_t n)
{
    const auto* f = reinterpret_cast<const float*>(x); // std::complex<float> is float[2]
    uint32_t bad = 0;
    for (size_t i = 0; i < 2 * n; ++i) {
        uint32_t b;
        std::memcpy(&b, f + i, sizeof b);
        bad |= static_cast<uint32_t>((b & 0x7f800000u) == 0x7f800000u);
    }
    return bad == 0;
}
// Every element finite.
inline bool all_finite(const double* x, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(x[i]))
            return false;
    return true;
}

} // namespace checks
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_CHECKS_H */
