// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The MIMO transmitter block: a MIMO mask's pilots, each on the transmit elements that
 *        send it, and the data on every element (docs/reference/arrays.md, MIMO masks).
 */
#ifndef INCLUDED_SEMS_BLOCKS_MIMO_PILOT_MAPPER_H
#define INCLUDED_SEMS_BLOCKS_MIMO_PILOT_MAPPER_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The MIMO transmitter: one output per transmit element, each an N x M frame.
 *
 * \details
 * \verbatim
   X_j[n,m] = a_ij · sqrt(E_p) · s_p · exp(jφ_i)   at pilot i of the mask (a_ij = mimo_mask::amplitude(i, j):
                                                   1 on its element, 1/sqrt(N_t) on each when every element sends it)
            = sqrt(E_d / N_t) · data              elsewhere, the same data on every element, row-major
   \endverbatim
 * so every pilot and every data symbol carries the energy one element would send alone. Output
 * j goes to the emulator's transmit input j (target_channel, target_channel_td with n_transmit =
 * N_t); SemS Pilot Extractor on the receive streams takes the same file and gives receive
 * element k's observation of pilot i as Σ_j a_ij H_{k·N_t+j}[n_i, m_i] (mimo_pilots()).
 *
 * Input: data symbols (gr_complex stream), N·(M − G) − N_p per frame (G guard subcarriers, zero
 * in every symbol); with N_p = N·(M − G) none, and the input may stay unconnected. Outputs:
 * gr_complex[M] per element, N per frame, each with keys::frame_tag (uint64 frame index) on its
 * first symbol; tags on data symbols move to every output's symbol that carries them.
 * Pilot and data power are energies per symbol (>= 0, finite), settable while running; a new
 * value takes effect at the next frame.
 */
class SEMS_API mimo_pilot_mapper : virtual public gr::block
{
public:
    typedef std::shared_ptr<mimo_pilot_mapper> sptr; ///< shared pointer to the block
    /*!
     * \brief Makes a MIMO pilot mapper.
     * \param mimo_mask_file  the MIMO mask (format sems.mimo_mask); its grid is the frame's
     * \param n_transmit      N_t, the outputs: must equal the file's
     * \param pilot_power     E_p
     * \param data_power      E_d
     * \param guard_subcarriers the frame's guard subcarriers: zero in every symbol; a pilot on one is refused
     * \return the block.
     * \throws std::invalid_argument naming the parameter and the problem (N_t: both values).
     */
    static sptr make(const std::string& mimo_mask_file,
                     int n_transmit,
                     double pilot_power = 1.0,
                     double data_power = 1.0,
                     const std::vector<int>& guard_subcarriers = {});
    /*! \brief Sets E_p from the next frame. \param energy pilot energy per symbol (>= 0, finite). \throws std::invalid_argument otherwise. */
    virtual void set_pilot_power(double energy) = 0;
    /*! \brief E_p. \return the pilot energy per symbol. */
    virtual double pilot_power() const = 0;
    /*! \brief Sets E_d from the next frame. \param energy data energy per symbol (>= 0, finite). \throws std::invalid_argument otherwise. */
    virtual void set_data_power(double energy) = 0;
    /*! \brief E_d. \return the data energy per symbol. */
    virtual double data_power() const = 0;
    /*! \brief The MIMO mask. \return it. */
    virtual const mimo_mask& mask() const = 0;
    /*! \brief Data symbols consumed per frame. \return N·(M − G) − N_p. */
    virtual int data_per_frame() const = 0;
    /*! \brief Frames started so far. \return the count. */
    virtual uint64_t frames() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_MIMO_PILOT_MAPPER_H */
