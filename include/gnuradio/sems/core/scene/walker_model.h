// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The walking human as 16 moving ellipsoid scatterers: the Boulic–Thalmann global human
 *        walking model (the `walker` micro-motion model of a scene target).
 *
 * \details Kinematics: R. Boulic, N. Magnenat-Thalmann, D. Thalmann, "A global human walking
 * model with real-time kinematic personification", The Visual Computer 6(6), 1990, as
 * implemented in V. C. Chen's MATLAB scripts (The Micro-Doppler Effect in Radar, Artech House,
 * 2011, ch. 4) and in MATLAB's backscatterPedestrian; the body's lengths follow
 * backscatterPedestrian's source, its ellipsoid radii Chen's. Scattering: each body segment is
 * an ellipsoid whose monostatic RCS (Chen) depends on the angle between the line of sight and
 * its axis. The equations, the segment table, the conventions, what comes from which source
 * and where the two implementations differ are in docs/reference/walker.md.
 *
 * Geometry. Body frame: x the walking direction, y to the walker's left, z up; origin the
 * pelvis centre (the model's spine origin), which moves with the body's mean velocity at the
 * hip-joint height. The radar is far away (one line of sight for all segments) in the
 * direction u = (cos ε cos θ, cos ε sin θ, sin ε) from the walker: θ the heading (the angle
 * from the walking direction to the direction towards the radar, counter-clockwise seen from
 * above; θ = 0 walks straight at the radar, the bulk radial velocity is then +v towards it),
 * ε the elevation of the radar seen from the pelvis (0: the radar in the horizontal plane).
 * A segment centre at body-frame position p has the radial displacement r = −p·u (+ = away
 * from the radar), relative to the mean-motion point; the target's bulk motion (range R,
 * radial velocity v·cos θ·cos ε towards the radar) is the caller's.
 */
#ifndef INCLUDED_SEMS_CORE_WALKER_MODEL_H
#define INCLUDED_SEMS_CORE_WALKER_MODEL_H

#include <gnuradio/sems/api.h>
#include <array>

namespace gr {
namespace sems {
/*! \brief The Boulic–Thalmann walking human (see walker_model.h). */
namespace walker {

/*! \brief Number of body segments (scatterers). */
constexpr int n_segments = 16;

/*!
 * \brief The 16 segments, in the order of MATLAB's backscatterPedestrian body parts.
 */
enum segment : int {
    left_foot = 0,   ///< ankle to toe
    right_foot,      ///< ankle to toe
    left_lower_leg,  ///< knee to ankle
    right_lower_leg, ///< knee to ankle
    left_upper_leg,  ///< hip joint to knee
    right_upper_leg, ///< hip joint to knee
    left_hip,        ///< pelvis centre to hip joint
    right_hip,       ///< pelvis centre to hip joint
    left_lower_arm,  ///< elbow to hand
    right_lower_arm, ///< elbow to hand
    left_upper_arm,  ///< shoulder to elbow
    right_upper_arm, ///< shoulder to elbow
    left_shoulder,   ///< base of the neck to shoulder
    right_shoulder,  ///< base of the neck to shoulder
    head,            ///< above the neck
    torso            ///< pelvis centre to the base of the neck
};

/*!
 * \brief Body proportions as fractions of the height H, as backscatterPedestrian's source
 *        (phased.internal.getHumanBodyParts) gives them. Chen's scripts share all but the ankle
 *        height, the neck and the lower arm (docs/reference/walker.md). The vertical chain sums
 *        to 1: ankle_height + lower_leg + upper_leg + torso + neck + head = H.
 */
namespace proportion {
constexpr double upper_leg = 0.245;             ///< hip joint to knee
constexpr double lower_leg = 0.246;             ///< knee to ankle
constexpr double ankle_height = 0.039;          ///< ankle above the sole; the toe lies this far below the ankle (Chen's leg has none)
constexpr double foot = 0.143;                  ///< ankle to toe, forward
constexpr double hip_half_width = 0.191 / 2.0;  ///< pelvis centre to hip joint
constexpr double torso = 0.288;                 ///< hip-joint line to the base of the neck
constexpr double neck = 0.052;                  ///< base of the neck to the head (Chen's head sits on the torso)
constexpr double head = 0.130;                  ///< the head
constexpr double shoulder_half_width = 0.259 / 2.0; ///< base of the neck to shoulder joint
constexpr double upper_arm = 0.188;             ///< shoulder to elbow
constexpr double lower_arm = 0.145;             ///< elbow to hand (Chen's is 0.152)
/*! \brief The hip-joint height H_t (the model's leg length): upper_leg + lower_leg + ankle_height. */
constexpr double hip_joint_height = upper_leg + lower_leg + ankle_height;
} // namespace proportion

/*! \brief One segment's ellipsoid: semi-axis length/2 along the segment, radius across it. */
struct segment_shape {
    const char* name; ///< e.g. "left foot"
    double length;    ///< the segment's length (ellipsoid axis 2c) as a fraction of the height
    double radius;    ///< its radius (ellipsoid semi-axes a = b) as a fraction of the height
};

/*!
 * \brief The 16 ellipsoids, indexed by #segment. Lengths from walker::proportion (the foot's is
 *        the ankle-to-toe distance hypot(foot, ankle_height)); radii are the absolute radii of
 *        Chen's scripts (foot 0.05 m, lower leg 0.06, upper leg 0.07, hip 0.07, lower arm 0.05,
 *        upper arm 0.06, shoulder 0.06, head 0.10, torso 0.15) divided by 1.8 m, so that they
 *        scale with the height.
 * \return the table.
 */
SEMS_API const std::array<segment_shape, n_segments>& segment_shapes();

/*! \brief The shortest walker accepted, in m (a height in other units, e.g. 180 cm, is refused). */
constexpr double min_height_m = 0.5;
/*! \brief The tallest walker accepted, in m. */
constexpr double max_height_m = 3.0;

/*! \brief The largest relative velocity RV = v/H_t of the model (Boulic's gait C ends at 3). */
constexpr double max_relative_velocity = 3.0;

/*!
 * \brief The leg length H_t of the model (the hip-joint height).
 * \param height_m the height H in m.
 * \return proportion::hip_joint_height · H in m.
 */
SEMS_API double leg_length_m(double height_m);

/*!
 * \brief The fastest walk the model allows at a height: max_relative_velocity · H_t.
 * \param height_m the height in m.
 * \return the speed in m/s (1.59 · height).
 */
SEMS_API double max_speed_mps(double height_m);

/*!
 * \brief The gait cycle (stride) duration of Boulic's model: the relative cycle length
 *        RL_c = 1.346·sqrt(RV) (in leg lengths) over the relative velocity RV = v/H_t,
 *        i.e. D_c = 1.346 / sqrt(RV) seconds.
 * \param height_m the height in m (min_height_m to max_height_m).
 * \param speed_mps the walking speed in m/s (0 to max_speed_mps(height)).
 * \return D_c in s; +infinity at speed 0 (a still body has no cycle).
 * \throws std::invalid_argument for a bad height or a speed outside the valid range.
 */
SEMS_API double cycle_duration_s(double height_m, double speed_mps);

/*! \brief A walker's parameters (SI units, angles in radians). */
struct walker_params {
    double height_m = 1.8;     ///< height H in m (min_height_m to max_height_m)
    double speed_mps = 1.4;    ///< walking speed v (0: a still body, no limb motion; up to 3·H_t)
    double heading_rad = 0.0;  ///< θ: from the walking direction to the direction towards the radar (0: walking at it)
    double phase_rad = 0.0;    ///< gait phase φ: the cycle is shifted by φ/(2π) cycles (any value)
    double elevation_rad = 0.0; ///< ε: elevation of the radar seen from the pelvis, in [−π/2, π/2]
};

/*! \brief A point or direction in the body frame (x forward, y left, z up), in m. */
using vec3 = std::array<double, 3>;

/*! \brief The 16 segments at one instant, in the body frame. */
struct body_pose {
    std::array<vec3, n_segments> centre; ///< segment centres relative to the mean-motion point (m)
    std::array<vec3, n_segments> axis;   ///< unit vectors along the segments (the ellipsoid c axes)
};

/*!
 * \brief The published trajectories at one cycle time u, for the right side (the left side
 *        follows the same trajectories half a cycle later). u = 0 is the right heel strike.
 */
struct gait_trajectories {
    double vertical_m;         ///< vertical translation of the pelvis, A_v·(sin 2π(2u − 0.35) − 1)
    double lateral_m;          ///< lateral translation (+ = left), A_l·sin 2π(u − 0.1)
    double forward_m;          ///< forward translation about the mean motion, A_fb·sin 2π(2u + 2φ_fb)
    double pelvis_forward_deg; ///< pelvis rotation forward/backward (< 0 leans the upper body forward)
    double pelvis_list_deg;    ///< pelvis rotation left/right (> 0 raises the left hip)
    double pelvis_torsion_deg; ///< pelvis torsion (< 0 turns the right hip forward)
    double hip_deg;            ///< hip flexion (> 0 swings the thigh forward)
    double knee_deg;           ///< knee flexion (> 0 swings the shank back)
    double ankle_deg;          ///< ankle flexion (> 0 raises the toe)
    double thorax_deg;         ///< thorax torsion (> 0 turns the left shoulder forward)
    double shoulder_deg;       ///< shoulder flexion (> 0 swings the upper arm forward)
    double elbow_deg;          ///< elbow flexion (> 0 swings the lower arm forward)
};

/*!
 * \brief A walker: the kinematics and scattering of one walking human, set up once per target
 *        (validates the parameters, builds the trajectories and the normalization) and then
 *        evaluated at any time without allocating.
 */
class SEMS_API walker_model
{
public:
    /*!
     * \brief Sets up the walker.
     * \param p the parameters.
     * \throws std::invalid_argument naming the parameter: height outside [0.5, 3] m; speed
     *         negative, not finite or above max_speed_mps(height) (the message names the speed,
     *         the height, the relative velocity and the valid range); heading, phase not finite;
     *         elevation outside [−π/2, π/2].
     */
    explicit walker_model(const walker_params& p);

    /*!
     * \brief The scatterers at time t: for each segment its centre's radial displacement and
     *        its amplitude.
     * \details r_s = −p_s·u (m, + = away from the radar, relative to the point moving with the
     * body's mean velocity). a_s = k·sqrt(σ_s) with the ellipsoid's monostatic RCS
     * σ_s = π a⁴c² / (a² sin²ψ_s + c² cos²ψ_s)² (a the radius, c half the length, ψ_s the angle
     * between the line of sight and the segment), k chosen once so that
     * Σ_s (mean over a gait cycle of a_s²) = 1 for these parameters. The gait phase is
     * t/D_c + φ/(2π) reduced to one cycle in double precision, so t = 10⁶ s is as exact as t = 1 s.
     * \param t_s time in s (finite; any sign).
     * \param r_m out: n_segments radial displacements in m, indexed by #segment.
     * \param amplitude out: n_segments amplitudes (dimensionless), indexed by #segment.
     * \throws std::invalid_argument if t_s is not finite.
     */
    void scatterers(double t_s, double* r_m, double* amplitude) const;

    /*!
     * \brief The scatterers at many instants: scatterers(t_s[n]) for n < count, a frame at a
     *        time (the joint angles' sines and cosines in one vectorised pass; equal to the
     *        one-instant values to within 2 ulp of each sine and cosine).
     * \param t_s count times in s (finite).
     * \param count the number of instants.
     * \param r_m out: n_segments x count radial displacements in m, segment s at t_s[n] in r_m[s·count + n].
     * \param amplitude out: n_segments x count amplitudes, laid out as r_m.
     * \param centre_m optional out (nullptr: not written): the segment centres in the body frame,
     *        3·n_segments x count values, coordinate i of segment s at t_s[n] in
     *        centre_m[(3·s + i)·count + n] (what an array needs: each segment's own direction).
     * \throws std::invalid_argument if a time is not finite.
     */
    void scatterers(const double* t_s, int count, double* r_m, double* amplitude, double* centre_m = nullptr) const;

    /*!
     * \brief The body at time t: segment centres and axes in the body frame.
     * \param t_s time in s (finite).
     * \param pose out: the pose.
     * \throws std::invalid_argument if t_s is not finite.
     */
    void pose(double t_s, body_pose& pose) const;

    /*!
     * \brief The published trajectories (Boulic et al., appendices A–D) at one cycle time.
     * \param u cycle time in [0, 1) (t/D_c + φ/(2π), reduced).
     * \return the translations and joint angles of the right side.
     * \throws std::invalid_argument if u is outside [0, 1).
     */
    gait_trajectories trajectories(double u) const;

    /*! \brief The relative velocity RV = v/H_t. \return RV. */
    double relative_velocity() const { return d_rv; }
    /*! \brief The gait cycle duration D_c. \return D_c in s (+infinity at speed 0). */
    double cycle_duration_s() const { return d_cycle_s; }
    /*! \brief The relative duration of support (stance) of one leg, 0.752 − 0.143/D_c. \return it. */
    double support_fraction() const { return d_support; }
    /*! \brief The unit line of sight u towards the radar, in the body frame. \return u. */
    const vec3& line_of_sight() const { return d_los; }
    /*! \brief The normalization k of the amplitudes. \return k in 1/m. */
    double amplitude_scale() const { return d_scale; }
    /*! \brief The parameters. \return them. */
    const walker_params& params() const { return d_params; }

private:
    // A periodic monotone cubic (MATLAB's pchip) through at most 5 knots per cycle.
    struct periodic_pchip {
        int n = 0;                      ///< knots per cycle
        std::array<double, 6> x{};      ///< knots, ascending, x[n] = x[0] + 1
        std::array<double, 5> y{}, b{}, c{}, d{}; ///< y + s·(b + s·(c + s·d)) on [x_i, x_{i+1})
        /*! \brief The value at cycle time u in [0, 1). \param u cycle time. \return the value. */
        double operator()(double u) const;
    };

    // The trajectories at cycle time u (rad, m); limbs [0] left, [1] right.
    struct gait_state {
        vec3 trans;
        double rot_fb, rot_lr, rot_tor, thorax;
        double hip[2], knee[2], ankle[2], shoulder[2], elbow[2];
    };
    gait_state state(double u) const;
    static constexpr int n_joint_angles = 14; // the angles a pose needs the sine and cosine of
    static void joint_angles(const gait_state& g, double* a);
    // The pose from the joint angles' sines and cosines (angle j at sn[j·stride], cs[j·stride]).
    void pose_from(const gait_state& g, const double* sn, const double* cs, int stride, body_pose& pose) const;
    void cycle_pose(double u, body_pose& pose) const;
    void scatter(const body_pose& pose, double* r_m, double* amplitude_unscaled) const;

    walker_params d_params;
    double d_height, d_rv, d_cycle_s, d_inv_cycle, d_phase_cycles, d_support;
    double d_trans_vert, d_trans_lat, d_trans_fb, d_trans_fb_cos, d_trans_fb_sin;
    double d_rot_fb, d_rot_lr, d_rot_tor, d_shoulder;
    periodic_pchip d_hip, d_knee, d_ankle, d_thorax, d_elbow;
    std::array<double, n_segments> d_a2, d_c2, d_sqrtpi_a2c; // a², c², sqrt(π)·a²·c in m
    vec3 d_los;
    double d_scale;
};

} // namespace walker
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_WALKER_MODEL_H */
