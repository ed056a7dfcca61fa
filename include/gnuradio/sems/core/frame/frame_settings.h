// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief OFDM frame settings (docs/design.md §1) and the quantities derived from them.
 */
#ifndef INCLUDED_SEMS_CORE_FRAME_SETTINGS_H
#define INCLUDED_SEMS_CORE_FRAME_SETTINGS_H

#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

/*! \brief GNU Radio's namespace. */
namespace gr {
/*! \brief gr-sems: semantic sensing over OFDM (frame, mask, scene, channel, blocks, learning, baselines). */
namespace sems {

/*! \brief The speed of light c in m/s; docs/design.md §1 uses c = 3e8 m/s exactly. */
constexpr double speed_of_light_mps = 3e8;

struct frame_difference;

/*!
 * \brief The OFDM frame: N symbols of M subcarriers over bandwidth B at carrier f_c.
 * \details The defaults here are the project's only C++ copy of the frame defaults (blocks and
 * bindings take them from here; GRC blocks repeat some as literals, which
 * python/sems/qa/qa_grc_defaults.py checks against them).
 */
struct SEMS_API frame_settings {
    int n_symbols = 32;             ///< N, OFDM symbols per frame (slow time)
    int n_subcarriers = 64;         ///< M, subcarriers per symbol
    double bandwidth_hz = 30e6;     ///< B in Hz
    double carrier_hz = 3e9;        ///< f_c in Hz
    double symbol_interval_s = 1e-3; ///< T, the symbol interval in s
    int cp_len = 16;                ///< cyclic prefix length in samples (time-domain path only)
    /*!
     * \brief Guard subcarriers: the columns m that carry neither pilots nor data (DC, band
     *        edges), ascending and distinct. Empty (the default): every subcarrier is used.
     */
    std::vector<int> guard_subcarriers;

    /*!
     * \brief Whether a subcarrier is a guard.
     * \param m the subcarrier (column of the grid).
     * \return true if m is listed in guard_subcarriers.
     */
    bool is_guard(int m) const;
    /*! \brief The subcarriers that may carry pilots and data. \return the non-guard columns, ascending. */
    std::vector<int> usable_subcarriers() const;
    /*! \brief N·(M − guards). \return the resource elements a pilot may occupy. */
    long long usable_elements() const;

    /*! \brief Δf = B/M in Hz. \return the subcarrier spacing. */
    double subcarrier_spacing_hz() const { return bandwidth_hz / n_subcarriers; }
    /*! \brief λ = c/f_c. \return the carrier wavelength in m. */
    double wavelength_m() const { return speed_of_light_mps / carrier_hz; }
    /*!
     * \brief N·M; validate() bounds it by limits::max_grid, and it never overflows.
     * \return the resource elements of one frame.
     * \throws std::invalid_argument if the (unvalidated) product is beyond the int range.
     */
    int grid_size() const
    {
        const long long g = static_cast<long long>(n_symbols) * n_subcarriers;
        if (g < 0 || g > 2147483647LL)
            throw std::invalid_argument("frame settings: grid N*M = " + std::to_string(g) + " is out of range");
        return static_cast<int>(g);
    }
    /*! \brief One delay index, 1/B. \return the delay resolution in s. */
    double delay_resolution_s() const { return 1.0 / bandwidth_hz; }
    /*! \brief One delay index in range, c/(2B). \return metres of range per delay index. */
    double range_per_delay_index_m() const { return speed_of_light_mps / (2.0 * bandwidth_hz); }
    /*! \brief The unambiguous delay 1/Δf. \return the maximum delay in s. */
    double max_delay_s() const { return 1.0 / subcarrier_spacing_hz(); }
    /*! \brief The unambiguous range c/(2Δf). \return the maximum range in m. */
    double max_range_m() const { return speed_of_light_mps * max_delay_s() / 2.0; }
    /*! \brief 1/(N·T). \return the Doppler resolution in Hz. */
    double doppler_resolution_hz() const { return 1.0 / (n_symbols * symbol_interval_s); }
    /*! \brief The unambiguous Doppler ±1/(2T). \return its magnitude in Hz. */
    double max_doppler_hz() const { return 1.0 / (2.0 * symbol_interval_s); }
    /*! \brief The unambiguous radial speed λ/(4T). \return its magnitude in m/s. */
    double max_speed_mps() const { return max_doppler_hz() * wavelength_m() / 2.0; }

    /*!
     * \brief Round-trip delay of a range.
     * \param range_m the range in m.
     * \return 2·range/c in s.
     */
    double delay_from_range(double range_m) const { return 2.0 * range_m / speed_of_light_mps; }
    /*!
     * \brief Range of a round-trip delay.
     * \param delay_s the delay in s.
     * \return c·delay/2 in m.
     */
    double range_from_delay(double delay_s) const { return delay_s * speed_of_light_mps / 2.0; }
    /*!
     * \brief Delay in delay-index units.
     * \param delay_s the delay in s.
     * \return delay·B (real valued).
     */
    double delay_index(double delay_s) const { return delay_s * bandwidth_hz; }
    /*!
     * \brief Doppler of a radial velocity.
     * \param v_mps radial velocity in m/s (positive: Doppler > 0).
     * \return 2v/λ in Hz.
     */
    double doppler_from_velocity(double v_mps) const { return 2.0 * v_mps / wavelength_m(); }

    /*!
     * \brief Checks every field.
     * \throws std::invalid_argument naming the parameter that is out of range.
     */
    void validate() const;

    /*! \brief The settings as JSON (the `frame` object of the file formats). \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object.
     * \param source names the file or context in errors.
     * \return the validated settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static frame_settings from_json(const nlohmann::json& j, const std::string& source);

    /*!
     * \brief The first field in which two frames differ (N, M, B, f_c, T, CP, guards, in that order).
     * \param o the other settings.
     * \return the field's name and both values as text; empty when the frames are equal.
     */
    std::optional<frame_difference> first_difference(const frame_settings& o) const;
    /*!
     * \brief Refuses another frame that differs in any field.
     * \param other the frame to compare with.
     * \param who names the caller in the error.
     * \param mine what this frame is (e.g. "the bundle's frame").
     * \param theirs what `other` is (e.g. "the stream's frame").
     * \throws std::invalid_argument "<who>: frame field <f> differs: <mine> has <a>, <theirs> has <b>".
     */
    void require_same(const frame_settings& other,
                      const std::string& who,
                      const std::string& mine,
                      const std::string& theirs) const;

    /*! \brief Field-wise equality. \param o the other settings. \return true if every field is equal. */
    bool operator==(const frame_settings& o) const;
    /*! \brief Negated operator==(). \param o the other settings. \return true if any field differs. */
    bool operator!=(const frame_settings& o) const { return !(*this == o); }
};

/*! \brief Where two frames differ: frame_settings::first_difference(). */
struct SEMS_API frame_difference {
    std::string field;  ///< the JSON key of the field (n_symbols, ..., guard_subcarriers)
    std::string first;  ///< the value in the frame first_difference() was called on
    std::string second; ///< the value in the other frame
};

/*!
 * \brief A frame file (`"format": "sems.frame"`, docs/reference/frame_files.md): a named
 *        frame with its description and the class library that fits it.
 */
struct SEMS_API frame_file {
    static constexpr const char* format_name = "sems.frame"; ///< the file's `format`
    static constexpr int format_version = 1;                 ///< the file's `version`

    std::string name;        ///< the frame's name (a preset's is its file name)
    std::string description; ///< free text for people
    std::string classes;     ///< the class library made for this frame (name or file); "" = none named
    std::string array;       ///< the array preset it suits (array_geometry::find: name or file); "" = none named
    frame_settings frame;    ///< the frame itself

    /*!
     * \brief A frame by name or path: `paper` (built in, the defaults), an existing file, or
     *        `<name>.json` in $SEMS_FRAMES_PATH, the user's folder
     *        (~/.local/share/gr-sems/models/frames, or under $XDG_DATA_HOME),
     *        $SEMS_SOURCE_DIR/models/frames, the source tree's models/frames, the installed
     *        share/gr-sems/models/frames.
     * \param name_or_path the name or file.
     * \return the frame file.
     * \throws std::invalid_argument listing every place searched.
     */
    static frame_file find(const std::string& name_or_path);
    /*!
     * \brief Reads a frame file.
     * \param path the file. \return the frame file.
     * \throws std::invalid_argument naming the file and the field.
     */
    static frame_file load(const std::string& path);
    /*!
     * \brief Reads a frame file's JSON.
     * \param j the JSON object. \param source names the origin in errors.
     * \return the frame file.
     * \throws std::invalid_argument naming `source` and the field.
     */
    static frame_file from_json(const nlohmann::json& j, const std::string& source);
    /*! \brief The file's JSON. \return the JSON object. */
    nlohmann::json to_json() const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_FRAME_SETTINGS_H */
