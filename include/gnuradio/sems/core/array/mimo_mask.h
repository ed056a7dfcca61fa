// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A MIMO pilot mask: which resource elements carry pilots, and which transmit element
 *        sends each (docs/reference/file_formats.md, "MIMO masks").
 *
 * \details An array with N_t transmit elements tells them apart by their pilots. A MIMO mask
 * is a pilot mask (its N_p resource elements) and, per pilot, the transmit element that sends
 * it, or every element at once. Every pilot carries the same total energy, so masks of one
 * N_p compare at equal pilot energy:
 *  - a pilot of one element j: that element sends s_p; receive element k observes
 *    H_{k·N_t+j}[n, m] (stream k·N_t + j of the channel's virtual elements: the pair alone);
 *  - a pilot of every element: each sends s_p/sqrt(N_t); receive element k observes
 *    Σ_j H_{k·N_t+j}[n, m]/sqrt(N_t), the transmit array's beam towards boresight.
 * The hand forms: the same pilots on every element (same_pilots()), time division (each symbol
 * of the pattern to one element in turn, time_division()) and frequency division (each
 * subcarrier in turn, frequency_division()). A learned mask assigns elements freely
 * (learning/array/mimo_mask_learner.h). What a receiver observes through the emulator is
 * core/channel/mimo_pilots.h.
 */
#ifndef INCLUDED_SEMS_CORE_MIMO_MASK_H
#define INCLUDED_SEMS_CORE_MIMO_MASK_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief A pilot mask with each pilot's transmit element (the file comment). */
class SEMS_API mimo_mask
{
public:
    static constexpr const char* format_name = "sems.mimo_mask"; ///< the file's `format`
    static constexpr int format_version = 1;                     ///< the file's `version`
    static constexpr int every_element = -1; ///< transmit[k] of a pilot every element sends

    /*!
     * \brief A mask and its pilots' transmit elements.
     * \param mask the pilots (equal energies: a MIMO mask shares each pilot's energy itself).
     * \param n_transmit N_t ≥ 1.
     * \param transmit per pilot in mask order: an element 0..N_t−1, or every_element.
     * \param source names the mask in errors.
     * \throws std::invalid_argument naming `source` for N_t < 1, a wrong length, an element
     *         out of range, or a mask with unequal pilot energies.
     */
    mimo_mask(pilot_mask mask, int n_transmit, std::vector<int> transmit, const std::string& source = "MIMO mask");

    /*! \brief Every pilot from every element (each at 1/sqrt(N_t)). \param mask the pilots. \param n_transmit N_t. \return the mask. */
    static mimo_mask same_pilots(const pilot_mask& mask, int n_transmit);
    /*!
     * \brief Time division: the symbols that hold pilots, in order, go to elements 0, 1, …,
     *        N_t−1, 0, … (every pilot of a symbol from one element).
     * \param mask the pilots. \param n_transmit N_t.
     * \return the mask.
     * \throws std::invalid_argument when the pilots sit on fewer than N_t symbols (an element would send none).
     */
    static mimo_mask time_division(const pilot_mask& mask, int n_transmit);
    /*!
     * \brief Frequency division: the subcarriers that hold pilots, in order, go to elements
     *        0, 1, …, N_t−1, 0, ….
     * \param mask the pilots. \param n_transmit N_t.
     * \return the mask.
     * \throws std::invalid_argument when the pilots sit on fewer than N_t subcarriers.
     */
    static mimo_mask frequency_division(const pilot_mask& mask, int n_transmit);

    /*! \brief Reads a MIMO mask file. \param path the file. \return the mask. \throws std::invalid_argument naming the file and the problem. */
    static mimo_mask load(const std::string& path);
    /*! \brief Parses a MIMO mask's JSON text. \param json_text the text. \param source names it in errors. \return the mask. \throws std::invalid_argument naming `source` and the problem. */
    static mimo_mask parse(const std::string& json_text, const std::string& source = "MIMO mask text");
    /*!
     * \brief Reads a MIMO mask from JSON: `n_transmit`, `mask` (a pilot mask's object) and
     *        `transmit`, one entry per pilot in the order `mask.pilots` lists them.
     * \param j the object. \param source names it in errors. \return the mask.
     * \throws std::invalid_argument naming `source` and the field.
     */
    static mimo_mask from_json(const nlohmann::json& j, const std::string& source);
    /*! \brief The file's JSON. \return the object. */
    nlohmann::json to_json() const;
    /*! \brief Writes the file. \param path the file. \throws std::invalid_argument naming the file if it cannot be written. */
    void save(const std::string& path) const;

    /*! \brief The pilots. \return the mask. */
    const pilot_mask& mask() const { return d_mask; }
    /*! \brief N_t. \return the transmit elements. */
    int n_transmit() const { return d_n_transmit; }
    /*! \brief Each pilot's element (or every_element), mask order. \return N_p values. */
    const std::vector<int>& transmit() const { return d_transmit; }
    /*!
     * \brief The amplitude element j sends pilot k with (relative to s_p).
     * \param k the pilot. \param j the element.
     * \return 1 for the pilot's own element, 1/sqrt(N_t) for a pilot of every element, else 0.
     */
    double amplitude(int k, int j) const;
    /*! \brief The pilots each element sends alone (every_element pilots not counted). \return N_t counts. */
    std::vector<int> pilots_per_element() const;
    /*! \brief Same pilots and elements. \param o the other mask. \return true if equal. */
    bool operator==(const mimo_mask& o) const;

private:
    pilot_mask d_mask;
    int d_n_transmit;
    std::vector<int> d_transmit;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_MIMO_MASK_H */
