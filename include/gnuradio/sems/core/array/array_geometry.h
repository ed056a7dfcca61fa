// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief An antenna array as data (`"format": "sems.array"`, docs/reference/file_formats.md):
 *        where the receive and transmit elements sit, and their element pattern.
 *
 * \details Coordinates (the convention of MATLAB's Phased Array System Toolbox): x is the
 * array's boresight, y points to its left, z up, all in metres from the array's phase centre.
 * A direction (azimuth φ from x towards y, elevation θ from the x–y plane towards z) has the unit
 * vector u = (cos θ cos φ, cos θ sin φ, sin θ). A ULA lies along y, centred on the origin
 * (element k at y = (k − (K−1)/2)·d); a URA lies in the y–z plane, centred, column index along
 * y and row index along z. The model that reads an array is steering.h's: element k of a path
 * in direction u sees the phase exp(j2π u·p_k/λ) and the delay τ − u·p_k/c (a plane wave).
 * One receive element and one transmit element at the origin is the single-antenna model.
 */
#ifndef INCLUDED_SEMS_CORE_ARRAY_GEOMETRY_H
#define INCLUDED_SEMS_CORE_ARRAY_GEOMETRY_H

#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <array>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief A point or vector in the array's frame (x boresight, y left, z up), in metres. */
using position3 = std::array<double, 3>;

/*! \brief The elements' pattern: the amplitude each element gives a direction. */
enum class element_pattern {
    isotropic, ///< 1 in every direction
    cosine     ///< u·x̂ = cos θ cos φ in the front half-space (x > 0), 0 behind (a patch-like element)
};
/*! \brief The name of a pattern. \param p the pattern. \return "isotropic" or "cosine". */
SEMS_API std::string element_pattern_name(element_pattern p);
/*!
 * \brief The pattern of a name.
 * \param name "isotropic" or "cosine".
 * \return the pattern.
 * \throws std::invalid_argument listing the known names.
 */
SEMS_API element_pattern element_pattern_from_name(const std::string& name);

/*!
 * \brief An array: receive elements, transmit elements and one element pattern.
 * \details Every constructor checks what it is given: at least one element of each kind, at most
 * limits::max_array_elements, finite positions, no two elements of one kind closer than
 * min_element_separation_m, positive spacings.
 */
class SEMS_API array_geometry
{
public:
    static constexpr const char* format_name = "sems.array"; ///< the file's `format`
    static constexpr int format_version = 1;                 ///< the file's `version`
    /*! \brief Two elements of one kind closer than this (1 µm) are refused as coincident. */
    static constexpr double min_element_separation_m = 1e-6;

    /*! \brief One receive and one transmit element at the origin: the single-antenna model. */
    array_geometry();

    /*!
     * \brief A uniform linear array of receive elements along y, centred on the origin, and one
     *        transmit element at the origin.
     * \param elements K ≥ 1. \param spacing_m d > 0 (λ/2 is the grating-lobe-free spacing).
     * \param pattern the element pattern.
     * \return the array.
     * \throws std::invalid_argument naming the parameter.
     */
    static array_geometry ula(int elements, double spacing_m, element_pattern pattern = element_pattern::isotropic);
    /*!
     * \brief A uniform rectangular array of receive elements in the y–z plane, centred, and one
     *        transmit element at the origin.
     * \param columns elements along y. \param rows elements along z.
     * \param spacing_y_m column spacing > 0. \param spacing_z_m row spacing > 0.
     * \param pattern the element pattern.
     * \return the array (element index = row·columns + column).
     * \throws std::invalid_argument naming the parameter.
     */
    static array_geometry ura(int columns, int rows, double spacing_y_m, double spacing_z_m,
                              element_pattern pattern = element_pattern::isotropic);
    /*!
     * \brief Any element positions.
     * \param receive receive element positions (≥ 1). \param transmit transmit element positions (≥ 1).
     * \param pattern the element pattern.
     * \param source names the origin in errors.
     * \return the array.
     * \throws std::invalid_argument naming `source`, the element and the problem.
     */
    static array_geometry from_positions(std::vector<position3> receive,
                                         std::vector<position3> transmit = { position3{ 0.0, 0.0, 0.0 } },
                                         element_pattern pattern = element_pattern::isotropic,
                                         const std::string& source = "array");

    /*!
     * \brief Reads an array file.
     * \param path the file. \return the array.
     * \throws std::invalid_argument naming the file and the field.
     */
    static array_geometry load(const std::string& path);
    /*!
     * \brief An array by name or path: an existing file, or `<name>.json` in $SEMS_ARRAYS_PATH,
     *        the user's folder, $SEMS_SOURCE_DIR/models/arrays, the source tree's models/arrays, the installed
     *        share/gr-sems/models/arrays (the presets the frame presets name, docs/reference/arrays.md).
     * \param name_or_path the name or file (a name with a '/' or ending in ".json" is a path).
     * \return the array.
     * \throws std::invalid_argument listing every place searched, or naming the file and the field.
     */
    static array_geometry find(const std::string& name_or_path);
    /*!
     * \brief Reads an array from JSON (a file's top level, or a scene's `array` object).
     * \param j the object. \param source names the origin in errors.
     * \param field the object's path in the file ("" at the top level).
     * \param top_level true: `format` and `version` are required.
     * \return the array.
     * \throws std::invalid_argument naming `source`, the field and the problem.
     */
    static array_geometry from_json(const nlohmann::json& j, const std::string& source,
                                    const std::string& field = "", bool top_level = true);
    /*! \brief The file's JSON (positions written out). \return the object. */
    nlohmann::json to_json() const;
    /*! \brief Writes the file. \param path the file. \throws std::invalid_argument naming the file. */
    void save(const std::string& path) const;

    /*! \brief The receive elements. \return their positions. */
    const std::vector<position3>& receive() const { return d_rx; }
    /*! \brief The transmit elements. \return their positions. */
    const std::vector<position3>& transmit() const { return d_tx; }
    /*! \brief The element pattern. \return it. */
    element_pattern pattern() const { return d_pattern; }
    /*! \brief N_r. \return the receive elements. */
    int n_receive() const { return static_cast<int>(d_rx.size()); }
    /*! \brief N_t. \return the transmit elements. */
    int n_transmit() const { return static_cast<int>(d_tx.size()); }
    /*!
     * \brief Whether this is the single-antenna model (one receive and one transmit element at
     *        the origin, isotropic): the emulator then draws today's frames bit for bit.
     * \return true for the single-antenna model.
     */
    bool is_single_antenna() const;
    /*!
     * \brief The largest |p| over every element (receive and transmit): the reach that bounds
     *        the aperture's delay, |u·p|/c ≤ reach/c.
     * \return the reach in m.
     */
    double reach_m() const;
    /*!
     * \brief Where each stream receives: receive element k with transmit element j at
     *        p_k + q_j (the virtual element of a monostatic MIMO array), receive-element-major
     *        (stream k·N_t + j). The one place that order and sum are written.
     * \return N_r·N_t offsets in m.
     */
    std::vector<position3> virtual_offsets() const;

private:
    std::vector<position3> d_rx, d_tx;
    element_pattern d_pattern = element_pattern::isotropic;
};

/*! \brief Equal arrays. \param a one array. \param b another. \return true when positions and pattern are equal. */
SEMS_API bool operator==(const array_geometry& a, const array_geometry& b);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_ARRAY_GEOMETRY_H */
