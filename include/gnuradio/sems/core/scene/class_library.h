// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Class libraries: the target classes a random scene draws from, as data
 *        (`"format": "sems.classes"`, docs/reference/class_libraries.md).
 *
 * \details Each class names its range and speed intervals and its micro-motion model with
 * an interval for every parameter, drawn uniformly per frame. The paper's table is the
 * built-in library `paper` (the default: its draws are the paper scenes' draws, bit for
 * bit); `kinematic` ships beside it (models/classes/kinematic.json): walking adults and
 * children, multirotors, a car with wheels, a bicyclist made of point scatterers.
 */
#ifndef INCLUDED_SEMS_CORE_CLASS_LIBRARY_H
#define INCLUDED_SEMS_CORE_CLASS_LIBRARY_H

#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {

namespace detail {
struct motion_template; // lib/core/scene/micro_motion_params.h
}

/*! \brief One class of a library: what a random scene draws a target of the class from. */
struct SEMS_API class_definition {
    std::string name;                  ///< the class name (labels, truth tags)
    std::string description;           ///< free text for people
    double range_min_m = 0.0;          ///< lower end of the range interval in m
    double range_max_m = 200.0;        ///< upper end of the range interval in m
    double speed_min_mps = 0.0;        ///< lower end of the speed interval in m/s
    double speed_max_mps = 0.0;        ///< upper end of the speed interval in m/s
    std::shared_ptr<const detail::motion_template> motion; ///< its micro-motion with intervals (null: none)
    /*! \brief Lower end of its mean RCS in dBsm, drawn per frame in a scene with a link budget (NaN: not given). */
    double rcs_min_dbsm = std::numeric_limits<double>::quiet_NaN();
    double rcs_max_dbsm = std::numeric_limits<double>::quiet_NaN(); ///< upper end of its mean RCS in dBsm
    /*! \brief Whether it gives an RCS (a scene with a link budget needs one). \return true when given. */
    bool has_rcs() const { return !std::isnan(rcs_min_dbsm); }
    /*!
     * \brief Lower end of the azimuth of its line of sight in rad, drawn per target in place of the
     *        scene's `random.azimuth_rad` (NaN: not given, the scene's applies).
     */
    double azimuth_min_rad = std::numeric_limits<double>::quiet_NaN();
    double azimuth_max_rad = std::numeric_limits<double>::quiet_NaN(); ///< upper end of its azimuth in rad
    /*!
     * \brief Lower end of the elevation of its line of sight in rad, drawn per target in place of
     *        the scene's `random.elevation_rad` (NaN: not given, the scene's applies).
     */
    double elevation_min_rad = std::numeric_limits<double>::quiet_NaN();
    double elevation_max_rad = std::numeric_limits<double>::quiet_NaN(); ///< upper end of its elevation in rad
    /*! \brief Whether it gives its own azimuth. \return true when given. */
    bool has_azimuth() const { return !std::isnan(azimuth_min_rad); }
    /*! \brief Whether it gives its own elevation. \return true when given. */
    bool has_elevation() const { return !std::isnan(elevation_min_rad); }
    /*! \brief The micro-motion model. \return "none", "sinusoid", "rotor", "walker", "wheels" or "scatterers". */
    std::string motion_model() const;
    /*! \brief The largest extent |r_s| any draw of its micro-motion reaches. \return the bound in m. */
    double max_extent_m() const;
    /*! \brief The largest instantaneous radial speed of a scatterer (bulk + micro-motion). \return the bound in m/s. */
    double max_scatterer_speed_mps() const;
    /*! \brief The largest micro-motion phase speed of the narrowband sinusoid, 2π f A. \return the bound in m/s. */
    double max_sinusoid_speed_mps() const;
};

/*! \brief A class library: classes by id (the label of a frame). */
class SEMS_API class_library
{
public:
    static constexpr const char* format_name = "sems.classes"; ///< the file's `format`
    static constexpr int format_version = 1;                   ///< the file's `version`

    /*! \brief The paper's table, built in (pedestrian, car, drone). \return the library. */
    static std::shared_ptr<const class_library> paper();
    /*!
     * \brief A library by name or path: `paper` (built in), an existing file, or `<name>.json`
     *        in $SEMS_CLASSES_PATH, the user's folder (~/.local/share/gr-sems/models/classes, or
     *        under $XDG_DATA_HOME), $SEMS_SOURCE_DIR/models/classes, the source tree's
     *        models/classes, the installed share/gr-sems/models/classes.
     * \param name_or_path the name or file.
     * \return the library.
     * \throws std::invalid_argument listing every place searched.
     */
    static std::shared_ptr<const class_library> find(const std::string& name_or_path);
    /*!
     * \brief Reads a library file.
     * \param path the file. \return the library.
     * \throws std::invalid_argument naming the file, the class and the field.
     */
    static std::shared_ptr<const class_library> load(const std::string& path);
    /*!
     * \brief Reads a library from JSON.
     * \param j the JSON object. \param source names the origin in errors.
     * \return the library.
     * \throws std::invalid_argument naming `source`, the class and the field.
     */
    static std::shared_ptr<const class_library> from_json(const nlohmann::json& j, const std::string& source);

    /*! \brief The file format's JSON (what bundles record). \return the JSON object. */
    nlohmann::json to_json() const;
    /*! \brief The library's name (`paper`, `kinematic`, or the file's). \return the name. */
    const std::string& name() const { return d_name; }
    /*! \brief The number of classes. \return the count. */
    int size() const { return static_cast<int>(d_classes.size()); }
    /*!
     * \brief One class by id.
     * \param id the class id. \return the class.
     * \throws std::invalid_argument on an unknown id.
     */
    const class_definition& at(int id) const;
    /*!
     * \brief A class id by name.
     * \param name the class name. \return its id.
     * \throws std::invalid_argument listing the known names.
     */
    int id_of(const std::string& name) const;
    /*! \brief The class names by id. \return the names. */
    std::vector<std::string> class_names() const;
    /*!
     * \brief Whether two libraries define the same classes (names, intervals, models).
     * \details Descriptions and RCS are not compared: an RCS only scales a class's power, and
     * a classifier is trained and used over a range of SNRs.
     * \param other the other library. \return true when their JSON (without description and RCS) is equal.
     */
    bool same_classes(const class_library& other) const;
    /*!
     * \brief Why two libraries differ, for an error message.
     * \param other the other library. \return "" when they are the same.
     */
    std::string difference(const class_library& other) const;

private:
    std::string d_name;
    std::string d_description;
    std::vector<class_definition> d_classes;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_CLASS_LIBRARY_H */
