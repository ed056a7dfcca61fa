// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the angle CRB, Bartlett and Capon beamforming and MUSIC over an array's pilots
 * (angle_estimators.h). The steering is core/array/steering.h's, the one the emulator uses. */
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/steering.h>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {

using cd = std::complex<double>;
using cmat = Eigen::MatrixXcd;

std::string num(double x) { return std::to_string(x); }

void check_common(const char* who, double wavelength_m, const angle_search& s)
{
    if (!(std::isfinite(wavelength_m) && wavelength_m > 0.0))
        throw std::invalid_argument(std::string(who) + ": wavelength_m must be > 0, got " + num(wavelength_m));
    if (!(std::isfinite(s.min_rad) && std::isfinite(s.max_rad) && s.min_rad >= -M_PI && s.max_rad <= M_PI &&
          s.min_rad < s.max_rad))
        throw std::invalid_argument(std::string(who) + ": the search interval [" + num(s.min_rad) + ", " +
                                    num(s.max_rad) + "] rad must lie in [-pi, pi] with min < max");
    if (s.grid < 8)
        throw std::invalid_argument(std::string(who) + ": search.grid must be >= 8, got " + std::to_string(s.grid));
}

void check_input(const char* who, const gr_complex* y, int elements, int snapshots)
{
    if (snapshots < 1)
        throw std::invalid_argument(std::string(who) + ": snapshots must be >= 1, got " + std::to_string(snapshots));
    for (size_t i = 0; i < size_t(elements) * size_t(snapshots); ++i)
        if (!std::isfinite(y[i].real()) || !std::isfinite(y[i].imag()))
            throw std::invalid_argument(std::string(who) + ": observation " + std::to_string(i) + " is not finite");
}

// R = Σ_t y_t y_tᴴ over the snapshots (element-major input).
cmat covariance(const gr_complex* y, int k, int l)
{
    cmat r = cmat::Zero(k, k);
    Eigen::VectorXcd v(k); // one snapshot, reused (a per-frame path: no allocation per snapshot)
    for (int t = 0; t < l; ++t) {
        for (int e = 0; e < k; ++e)
            v[e] = cd(y[size_t(e) * l + t]);
        // r += v vᴴ, column by column as Eigen's outer product does it, without its overhead
        // for small dynamic sizes (the array sink's search runs this every frame).
        for (int j = 0; j < k; ++j) {
            const cd c = std::conj(v[j]);
            for (int i = 0; i < k; ++i)
                r(i, j) += c * v[i];
        }
    }
    return r;
}

Eigen::VectorXcd steering(const array_geometry& a, double az, double el, double lambda, int first, int count)
{
    const auto s = steering_vector(a, az, el, lambda);
    Eigen::VectorXcd v(count);
    for (int i = 0; i < count; ++i)
        v[i] = s[size_t(first + i)];
    return v;
}

// Grid indices of the n largest local maxima (an end counts when above its one neighbour).
std::vector<int> strongest_peaks(const std::vector<double>& p, int n)
{
    std::vector<int> peaks;
    const int g = static_cast<int>(p.size());
    for (int i = 0; i < g; ++i) {
        const bool left = i == 0 || p[i] > p[i - 1];
        const bool right = i == g - 1 || p[i] >= p[i + 1];
        if (left && right)
            peaks.push_back(i);
    }
    std::sort(peaks.begin(), peaks.end(), [&](int a, int b) { return p[a] > p[b]; });
    if (static_cast<int>(peaks.size()) > n)
        peaks.resize(size_t(n));
    return peaks;
}

// The maximum of f between a grid peak's neighbours, by golden-section search.
template <class F>
double refine(F f, double lo, double hi)
{
    const double r = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = lo, b = hi, c = b - r * (b - a), d = a + r * (b - a);
    double fc = f(c), fd = f(d);
    for (int it = 0; it < 60 && b - a > 1e-12; ++it) {
        if (fc > fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    return 0.5 * (a + b);
}

// Smoothing needs a ULA: the virtual elements equally spaced along y, in order.
void check_smoothing(const char* who, const array_geometry& a, int subarray)
{
    const int k = a.n_receive() * a.n_transmit();
    if (subarray < 0 || subarray > k)
        throw std::invalid_argument(std::string(who) + ": subarray must be 0 (none) or in [1, " + std::to_string(k) +
                                    "] elements, got " + std::to_string(subarray));
    if (subarray == 0)
        return;
    const auto v = a.virtual_offsets();
    const double step = k > 1 ? v[1][1] - v[0][1] : 0.0;
    bool ula = k > 1 && step > 0.0;
    for (int e = 1; ula && e < k; ++e)
        ula = std::fabs(v[size_t(e)][0] - v[0][0]) < 1e-9 && std::fabs(v[size_t(e)][2] - v[0][2]) < 1e-9 &&
              std::fabs((v[size_t(e)][1] - v[size_t(e) - 1][1]) - step) < 1e-9 * (1.0 + std::fabs(step));
    if (!ula)
        throw std::invalid_argument(std::string(who) + ": spatial smoothing (subarray " + std::to_string(subarray) +
                                    ") needs a ULA: elements equally spaced along y, in order");
}

// Forward–backward smoothing: the mean of every m-element subarray's R and its
// exchange-conjugate (m = 0: R itself).
cmat smoothed(const cmat& r, int m)
{
    if (m == 0)
        return r;
    const int count = static_cast<int>(r.rows()) - m + 1;
    cmat s = cmat::Zero(m, m);
    for (int p = 0; p < count; ++p)
        s += r.block(p, p, m, m);
    const cmat j = Eigen::MatrixXcd::Identity(m, m).rowwise().reverse();
    return (s + j * s.conjugate() * j) / (2.0 * count);
}

double grid_angle(const angle_search& s, int i) { return s.min_rad + (s.max_rad - s.min_rad) * i / (s.grid - 1); }

// The n strongest peaks of the grid values p, each refined on f between its neighbours.
template <class F>
std::vector<double> refined_peaks(const angle_search& s, const std::vector<double>& p, F f, int n)
{
    std::vector<double> out;
    for (int i : strongest_peaks(p, n))
        out.push_back(refine(f, grid_angle(s, std::max(0, i - 1)), grid_angle(s, std::min(s.grid - 1, i + 1))));
    return out;
}

template <class F>
std::vector<double> peak_angles(const angle_search& s, F f, int n)
{
    std::vector<double> p(size_t(s.grid));
    for (int i = 0; i < s.grid; ++i)
        p[size_t(i)] = f(grid_angle(s, i));
    return refined_peaks(s, p, f, n);
}

// Beamforming's P(φ) = a(φ)ᴴ r a(φ) / ‖a(φ)‖² on the exact steering vectors (r and the array
// must outlive it). a(φ) is steering_vector()'s, element by element (the same g·element_phasor
// values), written into one buffer: the refinement evaluates it some fifty times a frame.
auto beam_power(const array_geometry& arr, double elevation, double lambda, const cmat& r, int k)
{
    return [pattern = arr.pattern(), offsets = arr.virtual_offsets(), elevation, lambda, &r, a = Eigen::VectorXcd(k),
            ar = Eigen::RowVectorXcd(k)](double az) mutable {
        const position3 u = direction_vector(az, elevation);
        const double g = element_pattern_amplitude(pattern, u);
        for (size_t e = 0; e < offsets.size(); ++e)
            a[Eigen::Index(e)] = g * element_phasor(u, offsets[e], lambda);
        const double n = a.squaredNorm();
        if (!(n > 0.0))
            return 0.0;
        ar.noalias() = a.adjoint() * r;
        return (ar * a)(0, 0).real() / n;
    };
}

// Beamforming's spectrum on the grid from its covariance: P_g = w_gᵀ r w_g*, w_g = conj(a_g)/‖a_g‖
// (steer: grid x K).
std::vector<double> grid_spectrum(const std::vector<std::complex<double>>& steer, int grid, int k, const cmat& r)
{
    std::vector<double> p(static_cast<size_t>(grid));
    Eigen::RowVectorXcd wr(k); // wᵀr, one buffer for the whole grid
    for (int i = 0; i < grid; ++i) {
        const Eigen::Map<const Eigen::VectorXcd> w(steer.data() + size_t(i) * k, k); // conj(a)/‖a‖
        wr.noalias() = w.transpose() * r;
        p[size_t(i)] = (wr * w.conjugate())(0, 0).real();
    }
    return p;
}

} // namespace

double angle_crb_rad2(const array_geometry& a, double azimuth_rad, double elevation_rad, double wavelength_m,
                      double energy_to_noise)
{
    if (!(std::isfinite(energy_to_noise) && energy_to_noise > 0.0))
        throw std::invalid_argument("angle_crb_rad2: energy_to_noise must be > 0, got " + num(energy_to_noise));
    if (!(std::isfinite(wavelength_m) && wavelength_m > 0.0))
        throw std::invalid_argument("angle_crb_rad2: wavelength_m must be > 0, got " + num(wavelength_m));
    // ȧ_k = ∂/∂φ [g(u) exp(j2π u·o_k/λ)]; the pattern's own slope is kept (a cosine element's
    // amplitude carries angle information too).
    const auto v = a.virtual_offsets();
    const position3 u = direction_vector(azimuth_rad, elevation_rad);
    const position3 du{ -std::cos(elevation_rad) * std::sin(azimuth_rad), std::cos(elevation_rad) * std::cos(azimuth_rad), 0.0 };
    const double g = element_pattern_amplitude(a.pattern(), u);
    const double dg = a.pattern() == element_pattern::cosine && u[0] > 0.0 ? 2.0 * u[0] * du[0] : 0.0;
    cd ad = 0.0;
    double aa = 0.0, dd = 0.0;
    for (const auto& o : v) {
        const cd e = element_phasor(u, o, wavelength_m);
        const cd ak = g * e;
        const cd dk = dg * e + g * e * cd(0.0, 2.0 * M_PI * projection_m(du, o) / wavelength_m);
        aa += std::norm(ak);
        ad += std::conj(ak) * dk;
        dd += std::norm(dk);
    }
    if (aa <= 0.0)
        throw std::invalid_argument("angle_crb_rad2: the array's pattern sees nothing at azimuth " + num(azimuth_rad));
    const double perp = dd - std::norm(ad) / aa;
    return 1.0 / (2.0 * energy_to_noise * perp);
}

beamforming_angle_estimator::beamforming_angle_estimator(const array_geometry& a, double elevation_rad,
                                                         double wavelength_m, angle_search search)
    : d_array(a), d_elevation(elevation_rad), d_lambda(wavelength_m), d_search(search)
{
    check_common("beamforming_angle_estimator", wavelength_m, search);
    const int k = a.n_receive() * a.n_transmit();
    d_steer.resize(size_t(search.grid) * size_t(k));
    for (int i = 0; i < search.grid; ++i) {
        const auto s = steering_vector(a, grid_angle(search, i), elevation_rad, wavelength_m);
        double norm = 0.0;
        for (const auto& x : s)
            norm += std::norm(x);
        for (int e = 0; e < k; ++e)
            d_steer[size_t(i) * k + e] = norm > 0.0 ? std::conj(s[size_t(e)]) / std::sqrt(norm) : 0.0;
    }
}

std::vector<double> beamforming_angle_estimator::spectrum(const gr_complex* y, int snapshots) const
{
    const int k = n_elements();
    check_input("beamforming_angle_estimator", y, k, snapshots);
    return grid_spectrum(d_steer, d_search.grid, k, covariance(y, k, snapshots));
}

std::vector<double> beamforming_angle_estimator::estimate(const gr_complex* y, int snapshots, int n_targets) const
{
    const int k = n_elements();
    if (n_targets < 1)
        throw std::invalid_argument("beamforming_angle_estimator: n_targets must be >= 1, got " + std::to_string(n_targets));
    check_input("beamforming_angle_estimator", y, k, snapshots);
    const cmat r = covariance(y, k, snapshots);
    const auto f = beam_power(d_array, d_elevation, d_lambda, r, k);
    // The grid from the steering vectors set up once (grid_spectrum), then f between neighbours.
    return refined_peaks(d_search, grid_spectrum(d_steer, d_search.grid, k, r), f, n_targets);
}

double beamforming_angle_estimator::refine(const gr_complex* y, int snapshots, double lo, double hi) const
{
    const int k = n_elements();
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
        throw std::invalid_argument("beamforming_angle_estimator::refine: needs lo < hi, got [" + std::to_string(lo) +
                                    ", " + std::to_string(hi) + "]");
    check_input("beamforming_angle_estimator", y, k, snapshots);
    const cmat r = covariance(y, k, snapshots);
    const auto f = beam_power(d_array, d_elevation, d_lambda, r, k);
    return ::gr::sems::refine(f, lo, hi);
}

capon_angle_estimator::capon_angle_estimator(const array_geometry& a, double elevation_rad, double wavelength_m,
                                             double loading, int subarray, angle_search search)
    : d_array(a), d_elevation(elevation_rad), d_lambda(wavelength_m), d_loading(loading), d_sub(subarray),
      d_search(search)
{
    const char* who = "capon_angle_estimator";
    check_common(who, wavelength_m, search);
    if (!(std::isfinite(loading) && loading >= 0.0))
        throw std::invalid_argument(std::string(who) + ": loading must be a finite number >= 0, got " + num(loading));
    check_smoothing(who, a, subarray);
}

std::vector<double> capon_angle_estimator::estimate(const gr_complex* y, int snapshots, int n_targets) const
{
    const char* who = "capon_angle_estimator";
    const int k = n_elements();
    if (n_targets < 1)
        throw std::invalid_argument(std::string(who) + ": n_targets must be >= 1, got " + std::to_string(n_targets));
    check_input(who, y, k, snapshots);
    cmat r = smoothed(covariance(y, k, snapshots), d_sub);
    const int dim = static_cast<int>(r.rows());
    const double delta = d_loading * r.trace().real() / dim;
    r.diagonal().array() += delta;
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<cmat>(r, Eigen::EigenvaluesOnly).eigenvalues();
    const Eigen::LDLT<cmat> solve(r);
    if (solve.info() != Eigen::Success || !(eig.minCoeff() > 1e-12 * eig.maxCoeff()))
        throw std::invalid_argument(std::string(who) + ": the sample covariance is singular (" +
                                    std::to_string(snapshots) + " snapshots, loading " + num(d_loading) +
                                    "): give more snapshots or a loading > 0");
    auto f = [&](double az) {
        const Eigen::VectorXcd a = steering(d_array, az, d_elevation, d_lambda, 0, dim);
        const double n = a.squaredNorm();
        const double q = a.dot(solve.solve(a)).real(); // aᴴ R⁻¹ a
        return n > 0.0 && q > 0.0 ? n / q : 0.0;
    };
    return peak_angles(d_search, f, n_targets);
}

music_angle_estimator::music_angle_estimator(const array_geometry& a, double elevation_rad, double wavelength_m,
                                             int n_targets, int subarray, angle_search search)
    : d_array(a), d_elevation(elevation_rad), d_lambda(wavelength_m), d_targets(n_targets), d_sub(subarray), d_search(search)
{
    const char* who = "music_angle_estimator";
    check_common(who, wavelength_m, search);
    const int k = a.n_receive() * a.n_transmit();
    const int dim = subarray > 0 ? subarray : k;
    check_smoothing(who, a, subarray);
    if (n_targets < 1 || n_targets >= dim)
        throw std::invalid_argument(std::string(who) + ": n_targets must be in [1, " + std::to_string(dim - 1) +
                                    "] (fewer than the " + std::to_string(dim) + " elements it searches with), got " +
                                    std::to_string(n_targets));
}

double music_angle_estimator::pseudo_spectrum(const std::vector<std::complex<double>>& noise, int dim, double az) const
{
    const Eigen::VectorXcd a = steering(d_array, az, d_elevation, d_lambda, 0, dim);
    const double n = a.squaredNorm();
    if (n <= 0.0)
        return 0.0;
    const int cols = static_cast<int>(noise.size()) / dim;
    const Eigen::Map<const cmat> en(noise.data(), dim, cols);
    const double proj = (en.adjoint() * a).squaredNorm() / n;
    return 1.0 / std::max(proj, 1e-300);
}

std::vector<double> music_angle_estimator::estimate(const gr_complex* y, int snapshots) const
{
    const int k = d_array.n_receive() * d_array.n_transmit();
    check_input("music_angle_estimator", y, k, snapshots);
    const cmat r = smoothed(covariance(y, k, snapshots), d_sub);
    const int dim = d_sub > 0 ? d_sub : k;
    Eigen::SelfAdjointEigenSolver<cmat> eig(r);
    const cmat en = eig.eigenvectors().leftCols(dim - d_targets); // ascending eigenvalues: the noise
    std::vector<std::complex<double>> noise(en.data(), en.data() + en.size());
    return peak_angles(d_search, [&](double az) { return pseudo_spectrum(noise, dim, az); }, d_targets);
}

} // namespace sems
} // namespace gr
