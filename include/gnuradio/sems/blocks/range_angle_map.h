// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the range–angle map block: one gr_complex[N_r·N_p] frame of an array's pilot
 * observations in (the pilot extractor's element-major output), one float[A·M] map in dB out
 * (core/array/range_angle.h: row a = azimuth −π/2 + π(a + ½)/A, column q = delay index q). The
 * live view beside the range–Doppler map: where the targets are in range and angle.
 *
 * A frame with a NaN/Inf observation is skipped and counted. Each map carries its frame's tags
 * (sems_frame, sems_truth).
 */
#ifndef INCLUDED_SEMS_RANGE_ANGLE_MAP_H
#define INCLUDED_SEMS_RANGE_ANGLE_MAP_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Range–angle map of each frame of an array's pilot observations (core/array/range_angle.h), in dB.
 * \details The array is the scene's (a preset's name, an array file, or its JSON text); its receive elements,
 * N_r, must be the extractor's elements, and it has one transmit element (an array with more is
 * refused: the extractor's streams are each receive element's sum over the transmit elements). Frame check: a mask file carries only its grid, refused
 * unless it is n_symbols x n_subcarriers.
 * \ingroup sems_blocks
 */
class SEMS_API range_angle_map : virtual public gr::block
{
public:
    typedef std::shared_ptr<range_angle_map> sptr; //!< shared pointer to the block

    /*!
     * \brief gr_complex[K·N_p] in, float[A·M] (dB) out, one item per frame.
     * \param array            a preset's name (e.g. ula8_3g), an array file (format sems.array) or its JSON text (starts with '{'): array_setting.h
     * \param mask_file        pilot mask JSON; "" to use pilot_positions
     * \param pilot_positions  flat pilot positions n·M+m; empty to use mask_file
     * \param n_symbols        N
     * \param n_subcarriers    M
     * \param carrier_hz       f_c (the wavelength of the steering vectors)
     * \param n_angles         A, azimuth rows over [−π/2, π/2]
     * \param window           "hann" or "rect" (over the subcarriers)
     * \return the block.
     * \throws std::invalid_argument naming the parameter and the problem.
     */
    static sptr make(const std::string& array,
                     const std::string& mask_file = "",
                     const std::vector<int>& pilot_positions = {},
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     double carrier_hz = frame_settings{}.carrier_hz,
                     int n_angles = 64,
                     const std::string& window = "hann");

    /*! \brief K, the array's streams. \return the elements. */
    virtual int n_elements() const = 0;
    /*! \brief N_p per element. \return the pilots. */
    virtual int n_pilots() const = 0;
    /*! \brief A. \return the map's azimuth rows. */
    virtual int n_angles() const = 0;
    /*! \brief Maps written. \return the count. */
    virtual uint64_t frames_out() const = 0;
    /*! \brief Frames skipped for a NaN/Inf observation. \return the count. */
    virtual uint64_t frames_skipped_nonfinite() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RANGE_ANGLE_MAP_H */
