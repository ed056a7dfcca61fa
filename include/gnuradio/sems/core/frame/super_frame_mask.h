// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Pilots across frames: a mask spanning a super-frame of F frames, each frame with its
 *        own pilots and the same count (docs/design.md §5; the file format in
 *        docs/reference/file_formats.md).
 *
 * \details Frame f of a stream carries the pilots of set f mod F, so the pattern repeats every
 * F frames and a receiver picks the set by the frame index (the `sems_frame` tag). Every set is
 * a pilot_mask of its own (positions, energies, phases, all validated as one), on the same
 * N x M grid, with the same pilot symbol and the same count N_p, so every frame's observation
 * vector has the same length. F = 1 is an ordinary pilot mask, and its file is the ordinary
 * mask file, bit for bit.
 */
#ifndef INCLUDED_SEMS_CORE_SUPER_FRAME_MASK_H
#define INCLUDED_SEMS_CORE_SUPER_FRAME_MASK_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief A pilot mask over a super-frame of F frames: set f mod F serves frame f. */
class SEMS_API super_frame_mask
{
public:
    /*!
     * \brief One frame's mask: F = 1.
     * \param mask the mask every frame carries.
     */
    explicit super_frame_mask(pilot_mask mask);
    /*!
     * \brief F sets, one per frame of the super-frame.
     * \param sets the masks of frames 0..F−1 (1 ≤ F ≤ limits::max_super_frames; the same N,
     *        M, pilot symbol and count).
     * \param origin how the super-frame was made (saved in the file; the sets' own origins are not).
     * \param source names the origin in errors.
     * \throws std::invalid_argument naming `source`, the set and both values that differ.
     */
    super_frame_mask(std::vector<pilot_mask> sets,
                     nlohmann::json origin = { { "kind", "explicit" } },
                     const std::string& source = "super-frame mask");
    /*!
     * \brief The same mask repeated: every frame of F carries `mask` (a hand pattern under a
     *        decoder that expects F sets).
     * \param mask the mask. \param n_frames F.
     * \return the super-frame.
     * \throws std::invalid_argument when F is out of range.
     */
    static super_frame_mask repeated(const pilot_mask& mask, int n_frames);

    /*!
     * \brief Reads a mask file: a super-frame file (`frames`) or an ordinary one (F = 1).
     * \param path the file. \return the mask.
     * \throws std::invalid_argument naming the file, the set and the problem.
     */
    static super_frame_mask load(const std::string& path);
    /*!
     * \brief Parses mask JSON text.
     * \param json_text the JSON. \param source names the text in errors.
     * \return the mask.
     * \throws std::invalid_argument naming `source` and the problem.
     */
    static super_frame_mask parse(const std::string& json_text, const std::string& source = "pilot mask text");
    /*!
     * \brief Reads a mask from JSON.
     * \param j the JSON object. \param source names the origin in errors.
     * \return the mask.
     * \throws std::invalid_argument naming `source` and the problem.
     */
    static super_frame_mask from_json(const nlohmann::json& j, const std::string& source);
    /*! \brief The file's JSON: F = 1 gives pilot_mask::to_json() exactly. \return the JSON object. */
    nlohmann::json to_json() const;
    /*! \brief The file's JSON text. \return the text. */
    std::string to_json_string() const;
    /*! \brief Writes the file. \param path the file. \throws std::invalid_argument naming the file if it cannot be written. */
    void save(const std::string& path) const;

    /*! \brief F. \return the frames of the super-frame. */
    int n_frames() const { return static_cast<int>(d_sets.size()); }
    /*! \brief N. \return the symbols per frame. */
    int n_symbols() const { return d_sets.front().n_symbols(); }
    /*! \brief M. \return the subcarriers per symbol. */
    int n_subcarriers() const { return d_sets.front().n_subcarriers(); }
    /*! \brief N_p, the same in every frame. \return the pilots per frame. */
    int pilots_per_frame() const { return d_sets.front().size(); }
    /*! \brief s_p. \return the pilot symbol. */
    gr_complex pilot_symbol() const { return d_sets.front().pilot_symbol(); }
    /*! \brief The sets. \return the masks of frames 0..F−1 of the super-frame. */
    const std::vector<pilot_mask>& sets() const { return d_sets; }
    /*!
     * \brief The set of frame f of the super-frame.
     * \param f in [0, F). \return its mask.
     * \throws std::out_of_range beyond F.
     */
    const pilot_mask& set(int f) const { return d_sets.at(static_cast<size_t>(f)); }
    /*! \brief The set a frame of a stream carries. \param frame_index the frame. \return set frame_index mod F. */
    const pilot_mask& for_frame(uint64_t frame_index) const { return d_sets[frame_index % d_sets.size()]; }
    /*! \brief How the super-frame was made. \return the origin object. */
    const nlohmann::json& origin() const { return d_origin; }

    /*!
     * \brief Checks that every set fits a frame (pilot_mask::check_frame).
     * \param fs the frame. \param who names the caller in errors.
     * \throws std::invalid_argument naming `who`, the set and the problem.
     */
    void check_frame(const frame_settings& fs, const std::string& who) const;
    /*!
     * \brief Checks that the super-frame is the one a stream or a decoder expects.
     * \param n_frames the F it expects. \param pilots_per_frame the N_p it expects.
     * \param who names the caller in errors. \param expected names what expects them.
     * \throws std::invalid_argument naming both values of whatever differs.
     */
    void check_shape(int n_frames, int pilots_per_frame, const std::string& who, const std::string& expected) const;

    /*! \brief Equality of every set and of F. \param o the other mask. \return true if equal. */
    bool operator==(const super_frame_mask& o) const { return d_sets == o.d_sets; }

private:
    std::vector<pilot_mask> d_sets;
    nlohmann::json d_origin;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_SUPER_FRAME_MASK_H */
