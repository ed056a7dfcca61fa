// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a scatterer target's return on the whole band, as a few separable terms (internal).
 *
 * Scatterer s of a target at radial displacement r_s (+ = away from the radar) returns, on
 * subcarrier m (RF frequency f_c + mΔf, wavenumber κ_m = 4π(f_c + mΔf)/c),
 *
 *     a_s · exp(-j κ_m r_s)           (a point)
 *     a_l · ∫_0^1 exp(-j κ_m e_l u) du  (a line from the body's reference to e_l: a blade, a spoke)
 *
 * which is exactly the per-scatterer delay and phase of the channel model. With a reference
 * wavenumber κ_ref (the middle of a band of subcarriers) and δk_m = κ_m − κ_ref,
 *
 *     exp(-j κ_m r) = Σ_p δk_m^p · G_p,   G_p = exp(-j κ_ref r) (−j r)^p / p!
 *
 * so the target's return is Σ_p δk_m^p · G_p(t): P+1 slow-time series, and per symbol one
 * polynomial in δk_m over the subcarriers (the frequency-domain model evaluates it by Horner's
 * rule, the time-domain one sums it as P+1 rows). The series is cut where its remainder, at
 * most Σ_s |a_s| (δk_max r_s)^{P+1}/(P+1)! (each scatterer's largest amplitude and reach, or
 * the body's bounds Σ|a| and r_max), is below truncation_tolerance (relative to a unit-power
 * target: below single precision, so the result is exact to float rounding); a band too wide
 * for P ≤ max_order is split into sub-bands with their own κ_ref.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_SCATTERER_MOMENTS_H
#define INCLUDED_SEMS_LIB_CORE_SCATTERER_MOMENTS_H

#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/walker_model.h>
#include <optional>
#include <complex>
#include <utility>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

constexpr double truncation_tolerance = 1e-7; // remainder bound, relative to a unit-power target
constexpr int max_order = 14;                 // P at most; a wider band is split into sub-bands

/* How a body's return is expanded on a frame: S sub-bands of subcarriers, P+1 terms each. */
struct expansion_plan {
    int order = 0;      // P
    int sub_bands = 1;  // S
    int band_len = 0;   // subcarriers per sub-band (the last may be shorter)
    int terms() const { return sub_bands * (order + 1); }
};

/* The plan for a body whose scatterers reach |r| ≤ extent_m with Σ|a| ≤ amplitude_sum. */
expansion_plan plan_expansion(const frame_settings& fs, double extent_m, double amplitude_sum);

/* The scatterers of one body at `count` instants t_0 .. t_{count−1}: scatterer i at instant n
 * is element i·count + n of each list (count = 1: one instant, one element per scatterer).
 * The rest is working memory of body_terms. */
struct body_snapshot {
    int count = 1;
    std::vector<double> point_r, point_a; // points: displacement, amplitude
    std::vector<double> line_r0, line_e, line_a; // lines from r0 to r0 + e: start, extent, amplitude
    // Per line (not per instant), optional: the index of the line that is its mirror image
    // through the reference point at every instant (extent exactly −e, the same amplitude,
    // both starting at r0 = 0), or −1; moments() computes such a pair once. Shorter than the
    // lines (or empty): the lines beyond it have no mirror.
    std::vector<int> line_mirror;
    // With cross_range (what an array needs): each scatterer's offset across the line of sight,
    // laid out as its displacement, h along increasing azimuth and v along increasing elevation
    // (m); for a line, its start's (h0, v0) and its extent's (he, ve). Empty otherwise.
    bool cross_range = false;
    std::vector<double> point_h, point_v, line_h0, line_v0, line_he, line_ve;
    std::vector<double> arg, sn, cs, x, y; // count values each: phases, their sines and cosines, scratch
    std::vector<double> re, im;            // moments: (order + 1) x count
    std::vector<double> e_re, e_im, l_re, l_im; // a line's integrals E_p, moments L_p: (order + 1) x count
    void clear()
    {
        point_r.clear();
        point_a.clear();
        line_r0.clear();
        line_e.clear();
        line_a.clear();
        line_mirror.clear();
        for (auto* v : { &point_h, &point_v, &line_h0, &line_v0, &line_he, &line_ve })
            v->clear();
    }
};

/* A body's scatterers through time: its snapshot at t, and the bounds its plan needs.
 * Amplitudes are normalised so the target's mean power at the carrier is 1: rotors in closed
 * form over independent rotor angles (at the carrier); wheels and walkers by their coherent
 * power averaged over one revolution / gait cycle and over the band; point scatterers the same
 * over their slowest harmonic's period (their powers are shares before that scaling). */
class body_model
{
public:
    explicit body_model(const scatterer_body& b, const frame_settings& fs);
    void snapshot(double t_s, body_snapshot& out) const { snapshots(&t_s, 1, out); }
    /* The scatterers at count instants; with cross_range also their offsets across the line of
     * sight (body_snapshot::point_h ...), which an array element's steering needs. */
    void snapshots(const double* t_s, int count, body_snapshot& out, bool cross_range = false) const;
    double extent_m() const { return d_extent; }
    double amplitude_sum() const { return d_amp_sum; }
    const scatterer_body& body() const { return d_b; }

private:
    void normalise_over_cycle(const frame_settings& fs, double period_s, int samples);
    scatterer_body d_b;
    std::optional<walker::walker_model> d_walker;
    double d_scale = 1.0; // the coherent normalisation (wheels, walker)
    double d_extent = 0.0, d_amp_sum = 0.0;
    double d_body_a = 0.0;  // the body's own point at r = 0
    double d_elem_a = 0.0;  // rotor blades / rim points: each one's amplitude
    double d_spoke_a = 0.0; // spokes
    struct rotor_group {    // rotors turning alike (rate, phase) coincide: one set of blades
        double rate_hz, phase_rad;
        int rotors;
    };
    std::vector<rotor_group> d_rotor_groups;
    std::vector<double> d_point_a; // scatterers: each one's amplitude
};

/* Where a body is seen from and by which array element: its reference point at range_m in
 * direction u (azimuth, elevation), e_h and e_v the unit vectors of increasing azimuth and
 * elevation there, and the element's offset and pattern (steering.h). */
struct body_steering {
    double range_m = 0.0;
    position3 u{ 1.0, 0.0, 0.0 }, e_h{ 0.0, 1.0, 0.0 }, e_v{ 0.0, 0.0, 1.0 };
    position3 offset{ 0.0, 0.0, 0.0 };
    element_pattern pattern = element_pattern::isotropic;
};

/* A path as `element` receives it (steering.h): its gain turned by the steering phasor, and for
 * a point path (body < 0) by the element pattern (a body's pattern is its scatterers', in
 * steer_snapshot); its delay moved by the plane wave's delay at the element. What both
 * emulators apply; the origin gives the path back unchanged. */
channel_path steered_path(const channel_path& p, const array_element& element, double wavelength_m);

/* The geometry of a body in direction (azimuth, elevation) at range_m, seen by `element`. */
body_steering make_body_steering(double range_m, double azimuth_rad, double elevation_rad, const array_element& element);

/* A snapshot (taken with cross_range) as one array element sees it, beyond the body's own
 * steering phasor and delay (which its path carries): every scatterer from its own direction.
 * Scatterer s sits at P_s = (R + r_s)·u + h_s·e_h + v_s·e_v; its direction u_s = P_s/|P_s| moves
 * its displacement by −(u_s − u)·o/2 (the plane wave's delay at offset o, two-way as r is) and
 * scales its amplitude by the element pattern g(u_s) (the path carries no pattern then). A line
 * keeps its straightness: its two ends are moved, the pattern taken at its middle. A scatterer
 * at the array's phase centre (|P_s| = 0) keeps the body's direction. out's mirror pairs are
 * dropped (the ends move apart). */
void steer_snapshot(const body_snapshot& base, const body_steering& geometry, body_snapshot& out);

/* δk_max of a plan's sub-bands (rad/m): its subcarrier rows hold (δk_m/δk_max)^p ∈ [−1, 1]. */
double band_scale(const frame_settings& fs, const expansion_plan& plan);

/* Term k = band·(P+1) + p of a plan on subcarrier m: (δk_m/δk_max)^p inside the band, 0 outside. */
double term_factor(const frame_settings& fs, const expansion_plan& plan, int term, int m);

/* Every term of a body at `count` instants t_s[0..count−1]:
 * out[n·plan.terms() + band·(P+1) + p] = G_p(t_s[n])·δk_max^p at the band's reference
 * wavenumber (snap is scratch). */
void body_terms(const body_model& model,
                const expansion_plan& plan,
                const frame_settings& fs,
                const double* t_s,
                int count,
                body_snapshot& snap,
                std::complex<double>* out);

/* The same at one instant: out[band·(P+1) + p] (plan.terms() values). */
inline void body_terms(const body_model& model,
                       const expansion_plan& plan,
                       const frame_settings& fs,
                       double t_s,
                       body_snapshot& snap,
                       std::complex<double>* out)
{
    body_terms(model, plan, fs, &t_s, 1, snap, out);
}

/* The plan for the scatterers of a snapshot: the same bound with each scatterer's own largest
 * amplitude a_s and reach r_s over the snapshot's instants, Σ_s a_s (δk_max r_s)^{P+1}/(P+1)!
 * (a line's reach: its farther end). */
expansion_plan plan_expansion(const frame_settings& fs, const body_snapshot& s);

/* body_terms of a snapshot already taken (its instants, its scatterers). */
void snapshot_terms(body_snapshot& snap, const expansion_plan& plan, const frame_settings& fs, std::complex<double>* out);

/* Whether two bodies move alike (same model, parameters, speed and heading): a body_model set
 * up for one serves the other. */
inline bool same_body(const scatterer_body& a, const scatterer_body& b)
{
    return a.speed_mps == b.speed_mps && a.heading_rad == b.heading_rad && a.elevation_rad == b.elevation_rad &&
           a.motion == b.motion;
}

/* G_p for p = 0..P of a snapshot's instants at reference wavenumber kappa_ref, in the
 * snapshot's s.re, s.im: G_p(t_n) = s.re[p·count + n] + j s.im[p·count + n]. */
void moments(body_snapshot& s, double kappa_ref, int order);

/* E_p(z) = ∫_0^1 s^p exp(-j z s) ds for p = 0..order (a line's moments): out[p]. */
void line_integrals(double z, int order, std::complex<double>* out);

/* The same given e = exp(-j z). */
void line_integrals(double z, std::complex<double> e, int order, std::complex<double>* out);

/* One rotor of `blades` unit-amplitude blades, x0 = κ(L/2)cos β: the mean over its angle of its
 * return B and of |B|² (the rotor model's power normalisation). */
std::pair<std::complex<double>, double> rotor_mean_moments(double x0, int blades);

/* mean over θ ∈ [0, 2π) of sinc²(x0 cos θ), sinc(x) = sin x / x: a line's mean power. */
double mean_sinc_squared(double x0);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_SCATTERER_MOMENTS_H */
