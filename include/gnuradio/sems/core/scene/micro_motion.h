// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Targets as moving scatterers: the micro-motion models of a target
 *        (docs/reference/micro_motion.md).
 *
 * \details A target's return is the coherent sum of its scatterers, each at its own range
 * R + r_s(t) (r_s its radial displacement from the body, + = away from the radar):
 * \verbatim
   H[n,m] += α · exp(j2π ν t_n) · Σ_s a_s(t_n) · exp(-j2π m Δf · 2(R + r_s(t_n))/c) · exp(-j (4π/λ) r_s(t_n))
   \endverbatim
 * The paper's sinusoid (scene.h, micro_doppler) is the narrowband special case. The models
 * here are exact per scatterer: rotor blades (V. C. Chen, *The Micro-Doppler Effect in
 * Radar*, ch. 4), a walking person (Boulic–Thalmann, walker_model.h), rolling wheels, and
 * any set of point scatterers with harmonic radial motion.
 */
#ifndef INCLUDED_SEMS_CORE_MICRO_MOTION_H
#define INCLUDED_SEMS_CORE_MICRO_MOTION_H

#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The paper's micro-Doppler (model `sinusoid`): a sinusoidal displacement
 *        r = −A·sin(2π f_md t + φ), applied narrowband as exp(j (4π/λ) A sin(2π f_md t + φ)).
 */
struct SEMS_API micro_doppler {
    double rate_hz = 0.0;     ///< f_md = ω / 2π
    double amplitude_m = 0.0; ///< displacement A
    double phase_rad = 0.0;   ///< φ (random scenes draw it per frame)
};

/*!
 * \brief Rotor blades as line scatterers (Chen): blade k of K on a rotor has its point at
 *        distance l from the hub displaced l·cos β·cos(2π f_rot t + φ + 2πk/K).
 *
 * \details A blade returns L·sinc(x)·exp(−jx), x = (4π/λ)(L/2)·cos β·cos(2π f_rot t + φ + 2πk/K)
 * at the carrier (at subcarrier m, λ of f_c + mΔf). The hubs sit at the body's reference
 * point. The body returns a share `body_power` of the target's mean power, the blades
 * the rest, averaged over a revolution.
 */
struct SEMS_API rotor_motion {
    int rotors = 4;                         ///< rotors on the body
    int blades = 2;                         ///< blades K per rotor
    double blade_length_m = 0.1;            ///< L, hub to tip
    std::vector<double> rotation_hz{ 100.0 }; ///< f_rot in revolutions per second: one value, or one per rotor
    std::vector<double> phase_rad{ 0.0 };   ///< φ: one value, or one per rotor
    double elevation_rad = 0.0;             ///< β, the radar's elevation over the rotor plane
    double body_power = 0.5;                ///< the body's share of the mean power, in [0, 1]
};

/*!
 * \brief A walking person: the Boulic–Thalmann global human walking model, 16 body
 *        segments as ellipsoid scatterers (walker_model.h). The speed and heading are the target's.
 */
struct SEMS_API walker_motion {
    double height_m = 1.8; ///< the person's height
    double phase_rad = 0.0; ///< gait phase: a shift of the walking cycle
};

/*!
 * \brief A vehicle's body plus wheels rolling at its speed.
 *
 * \details The wheels sit on axles spread over the wheelbase, two per axle (left and right of
 * the track; an odd last one in the middle), so hub h is displaced r_h = −(x_h cos θ + y_h sin θ)
 * from the body's centre (θ the heading). Wheel w's rim point i sits at angle
 * ψ = 2π i/rim_points + φ_w and is displaced r_h − R·cos θ·sin(v t/R + ψ) (the sinusoid with
 * A = R cos θ at v/(2πR) rev/s); spoke k is the line from the hub to the rim at angle
 * 2π k/spokes + φ_w (the rotor formula with L = R). Seen head-on the wheels' radial
 * velocities span 0 to twice the body's. The body returns a share `body_power` of the mean
 * power, the wheels the rest, each rim point and spoke the same.
 */
struct SEMS_API wheels_motion {
    int wheels = 4;             ///< wheels on the vehicle
    double wheel_radius_m = 0.3; ///< R
    int rim_points = 8;         ///< point scatterers on each rim (0: none)
    int spokes = 0;             ///< line scatterers from the hub to the rim (0: none)
    double body_power = 0.8;    ///< the body's share of the mean power, in [0, 1]
    double wheelbase_m = 2.7;   ///< front axle to rear axle
    double track_m = 1.6;       ///< left wheel to right wheel
    double phase_rad = 0.0;     ///< φ_0, the first wheel's rotation angle at t = 0 (wheel w: φ_0 + w·2.39996, the golden angle, so rims are not aligned)
};

/*! \brief One harmonic of a point scatterer's radial motion: r += −A sin(2π f t + φ). */
struct SEMS_API harmonic {
    double amplitude_m = 0.0; ///< A
    double rate_hz = 0.0;     ///< f
    double phase_rad = 0.0;   ///< φ
};

/*!
 * \brief A point scatterer with harmonic motion along the body's heading,
 *        r = −cos θ · Σ_h A_h sin(2π f_h t + φ_h) on the line of sight (θ the heading).
 *
 * \details As with wheels and limbs, the motion is along the direction the body moves: a
 * target approaching head-on (θ = 0) sees it whole, one seen side-on (θ = π/2) sees none of it.
 */
struct SEMS_API point_scatterer {
    double power = 1.0;              ///< its share of the target's mean power (shares are normalised to sum 1)
    std::vector<harmonic> harmonics; ///< none: a fixed point on the body
};

/*! \brief Any set of point scatterers: a new target defined in JSON. */
struct SEMS_API scatterers_motion {
    std::vector<point_scatterer> scatterers; ///< at least one
};

/*! \brief A target's micro-motion, one of the scatterer models. */
using micro_motion = std::variant<rotor_motion, walker_motion, wheels_motion, scatterers_motion>;

/*! \brief Equal parameters. \param a one motion. \param b another. \return true when every field is equal. */
SEMS_API bool operator==(const rotor_motion& a, const rotor_motion& b);
/*! \brief Equal parameters. \param a one motion. \param b another. \return true when every field is equal. */
SEMS_API bool operator==(const walker_motion& a, const walker_motion& b);
/*! \brief Equal parameters. \param a one motion. \param b another. \return true when every field is equal. */
SEMS_API bool operator==(const wheels_motion& a, const wheels_motion& b);
/*! \brief Equal parameters. \param a one motion. \param b another. \return true when every field is equal. */
SEMS_API bool operator==(const scatterers_motion& a, const scatterers_motion& b);

/*! \brief The model's name ("rotor", "walker", "wheels", "scatterers"). \param m the motion. \return its name. */
SEMS_API std::string micro_motion_model(const micro_motion& m);

/*!
 * \brief Checks every field of a micro-motion.
 * \param m the motion.
 * \param source names the file or text in errors.
 * \param field the motion's path in the file (e.g. "targets[0].micro_motion").
 * \throws std::invalid_argument naming `source`, the field and the problem.
 */
SEMS_API void validate_micro_motion(const micro_motion& m, const std::string& source, const std::string& field);

/*!
 * \brief The largest radial displacement |r_s(t)| any scatterer of the motion reaches.
 * \param m the motion.
 * \return the bound in m (the walker's from its height).
 */
SEMS_API double micro_motion_extent_m(const micro_motion& m);

/*!
 * \brief The largest radial speed |dr_s/dt| of the motion's scatterers relative to the body.
 * \param m the motion.
 * \param speed_mps the target's speed (wheels and walker move with it).
 * \return the bound in m/s.
 * \throws std::invalid_argument for a walker outside its model's range of heights and speeds.
 */
SEMS_API double micro_motion_peak_speed_mps(const micro_motion& m, double speed_mps);

/*!
 * \brief The motion's JSON object (without the "model" key's siblings it does not use).
 * \param m the motion.
 * \return {"model": name, ...}.
 */
SEMS_API nlohmann::json micro_motion_to_json(const micro_motion& m);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_MICRO_MOTION_H */
