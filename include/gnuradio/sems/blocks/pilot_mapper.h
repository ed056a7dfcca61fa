// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The learned-pilot OFDM transmitter block (docs/design.md §2).
 */
#ifndef INCLUDED_SEMS_BLOCKS_PILOT_MAPPER_H
#define INCLUDED_SEMS_BLOCKS_PILOT_MAPPER_H

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
 * \brief The learned-pilot OFDM transmitter (docs/design.md §2): places the pilot mask's pilots and the data symbols on an N x M frame.
 *
 * \details
 * \verbatim
   X_s[n,m] = sqrt(E_p · p_k) · s_p · exp(jφ_k)   at pilot k of the mask P
            = sqrt(E_d) · data                     elsewhere, data taken in row-major order
   \endverbatim
 *
 * p_k is pilot k's relative energy from the mask file's `power` list (mean 1; all 1 without
 * it, and always 1 with pilot_positions).
 *
 * Input: data symbols (gr_complex stream). Output: gr_complex[M], one OFDM symbol in
 * the frequency domain, N per frame; a frame consumes N·(M − G) − N_p data symbols, G the
 * number of guard subcarriers, which carry zero (no pilot may sit on one).
 * Tag keys::frame_tag (uint64 frame index, counting from 0) on the first symbol of
 * every frame. Tags on data symbols move to the output symbol that carries them.
 *
 * The mask comes from a mask file (super_frame_mask::load) or from explicit flat positions
 * n·M+m: exactly one of the two. With a file, pilot_symbol must equal the file's. A file may
 * span a super-frame of F frames, each with its own pilots and the same count: frame f (the
 * index of its keys::frame_tag) carries set f mod F, so the pattern repeats every F frames.
 *
 * Frame check: the mask must be n_symbols x n_subcarriers with no pilot on guard_subcarriers
 * (pilot_mask::check_frame names the field and both values, or the pilot and its guard); a mask
 * file carries no bandwidth, carrier, symbol interval or CP, and the block has no parameter for
 * them.
 *
 * N_p = N·(M − G) (pilots only, every usable cell a pilot; G guard subcarriers): the frame
 * carries no data, the block consumes no input and acts as a source of pilot-only frames; the input may then be left unconnected
 * (bound the output with a head block). With data positions an input is required.
 *
 * Pilot and data power are energies per symbol (>= 0, finite), settable while running;
 * a new value takes effect at the next frame, so a frame is never split between two powers.
 */
class SEMS_API pilot_mapper : virtual public gr::block
{
public:
    typedef std::shared_ptr<pilot_mapper> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a pilot mapper.
     * \param mask_file        pilot mask JSON (docs/design.md §4); "" to use pilot_positions
     * \param pilot_positions  flat pilot positions n·M+m (any order); empty to use mask_file
     * \param n_symbols        N, OFDM symbols per frame
     * \param n_subcarriers    M, subcarriers (output vector length)
     * \param pilot_symbol     s_p (non-zero); must match the mask file's when a file is given
     * \param pilot_power      E_p
     * \param data_power       E_d
     * \param guard_subcarriers the frame's guard subcarriers (frame_settings::guard_subcarriers):
     *                         zero in every symbol; a pilot on one is refused
     * \return the block.
     * \throws std::invalid_argument naming the parameter and the problem.
     */
    static sptr make(const std::string& mask_file = "",
                     const std::vector<int>& pilot_positions = {},
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     gr_complex pilot_symbol = gr_complex(1.0f, 0.0f),
                     double pilot_power = 1.0,
                     double data_power = 1.0,
                     const std::vector<int>& guard_subcarriers = {});

    /*!
     * \brief Sets E_p from the next frame.
     * \param energy pilot energy per symbol (>= 0, finite).
     * \throws std::invalid_argument if negative or not finite.
     */
    virtual void set_pilot_power(double energy) = 0;
    /*! \brief E_p. \return the pilot energy per symbol. */
    virtual double pilot_power() const = 0;
    /*!
     * \brief Sets E_d from the next frame.
     * \param energy data energy per symbol (>= 0, finite).
     * \throws std::invalid_argument if negative or not finite.
     */
    virtual void set_data_power(double energy) = 0;
    /*! \brief E_d. \return the data energy per symbol. */
    virtual double data_power() const = 0;

    /*! \brief The pilot mask of frame 0 (the only one unless the mask spans a super-frame). \return the mask. */
    virtual const pilot_mask& mask() const = 0;
    /*! \brief The pilot sets of every frame of the super-frame (F = 1 for one frame's mask). \return the masks. */
    virtual const super_frame_mask& super_frame() const = 0;
    /*! \brief N_p. \return the pilots per frame. */
    virtual int n_pilots() const = 0;
    /*! \brief Data symbols consumed per frame. \return N·(M − G) − N_p (G guard subcarriers). */
    virtual int data_per_frame() const = 0;
    /*! \brief Frames started so far. \return the count. */
    virtual uint64_t frames() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_PILOT_MAPPER_H */
