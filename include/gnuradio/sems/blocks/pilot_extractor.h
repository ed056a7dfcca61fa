// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The pilot extractor block (docs/design.md §3).
 */
#ifndef INCLUDED_SEMS_BLOCKS_PILOT_EXTRACTOR_H
#define INCLUDED_SEMS_BLOCKS_PILOT_EXTRACTOR_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The pilot extractor (docs/design.md §3): gr_complex[M] in (one input per receive element), one gr_complex[n_elements·N_p] of pilot observations Y/(sqrt(p_k)·s_p·exp(jφ_k)) per frame out.
 *
 * \details The output is the pilot observations Y[n,m]/(sqrt(p_k)·s_p·exp(jφ_k)) at the mask
 * positions, in mask order (row-major, sorted by (n, m)), with p_k pilot k's relative
 * energy from the mask file (1 without a `power` list) and φ_k its phase (0 without `phases`): pilot k's noise is scaled by
 * 1/sqrt(p_k). E_p is not divided out: with pilot power E_p and a noiseless channel the
 * output is sqrt(E_p)·H at the pilots.
 *
 * Frames are aligned to keys::frame_tag tags when present and counted (N symbols
 * each) otherwise. A partial frame (a frame tag arrives before N symbols were
 * collected, or the stream starts or ends mid-frame) is dropped and counted; a frame with a
 * NaN/Inf anywhere in its symbols is skipped and counted. Every output item carries
 * a keys::frame_tag (the input's value, or the counted index on an untagged stream)
 * and the tags of its frame's symbols (keys::truth_tag among them).
 *
 * The mask is given as in pilot_mapper: a mask file or flat positions n·M+m. A mask file
 * may span a super-frame of F frames (super_frame_mask): frame f is read at the pilots of
 * set f mod F, f the frame's index (its keys::frame_tag, or the count), so the output is
 * N_p observations in that set's mask order, as the mapper placed them.
 *
 * Arrays: with n_elements inputs (one per receive element, as target_channel's outputs) the
 * output is gr_complex[n_elements·N_p] per frame, element-major (element k's pilots at
 * k·N_p .. k·N_p + N_p − 1), all elements read at the same pilots. The inputs advance in
 * lockstep; frames align to input 0's tags (which ride with the output), and a NaN/Inf on any
 * input skips the frame.
 *
 * Frame check: a mask file carries only its grid, refused unless it is n_symbols x n_subcarriers
 * (pilot_mask::check_frame names the field and both values); the block has no guard, bandwidth,
 * carrier, symbol-interval or CP parameter, so it cannot compare those (pilot_mapper refuses a
 * pilot on its guards).
 */
class SEMS_API pilot_extractor : virtual public gr::block
{
public:
    typedef std::shared_ptr<pilot_extractor> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a pilot extractor.
     * \param mask_file        pilot mask JSON (a MIMO mask file gives its pilots, every transmit
     *                         element's together: mimo_pilot_mapper's); "" to use pilot_positions
     * \param pilot_positions  flat pilot positions n·M+m; empty to use mask_file
     * \param n_symbols        N
     * \param n_subcarriers    M (input vector length)
     * \param pilot_symbol     s_p, the observations are divided by it; must match the file's
     * \param n_elements       inputs, one per receive element (1..limits::max_array_elements)
     * \return the block.
     * \throws std::invalid_argument naming the parameter and the problem.
     */
    static sptr make(const std::string& mask_file = "",
                     const std::vector<int>& pilot_positions = {},
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     gr_complex pilot_symbol = gr_complex(1.0f, 0.0f),
                     int n_elements = 1);

    /*! \brief The pilot mask of frame 0 (the only one unless the mask spans a super-frame). \return the mask. */
    virtual const pilot_mask& mask() const = 0;
    /*! \brief The pilot sets of every frame of the super-frame (F = 1 for one frame's mask). \return the masks. */
    virtual const super_frame_mask& super_frame() const = 0;
    /*! \brief N_p, the pilots per element. \return them (the output vector is n_elements()·N_p). */
    virtual int n_pilots() const = 0;
    /*! \brief The inputs, one per receive element. \return their number. */
    virtual int n_elements() const = 0;

    /*! \brief Frames written. \return the count. */
    virtual uint64_t frames_out() const = 0;
    /*! \brief Partial frames dropped (a frame tag before N symbols, a mid-frame start or end). \return the count. */
    virtual uint64_t frames_dropped_partial() const = 0;
    /*! \brief Frames skipped for a NaN/Inf symbol. \return the count. */
    virtual uint64_t frames_skipped_nonfinite() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_PILOT_EXTRACTOR_H */
