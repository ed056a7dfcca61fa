// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: how the mapper and the extractor turn their block parameters into a
 * super_frame_mask (internal to the library). One place, so both ends of the chain read
 * the same parameters the same way: a mask file (one frame's mask, a super-frame of F
 * sets, or a MIMO mask's pilots) OR explicit flat positions n·M+m (one frame's).
 */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_BLOCK_MASK_H
#define INCLUDED_SEMS_LIB_BLOCKS_BLOCK_MASK_H

#include "core/common/checks.h"
#include "core/common/json_read.h"
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {

inline std::string complex_text(gr_complex z)
{
    std::ostringstream s;
    s << "(" << z.real() << (z.imag() < 0 ? "" : "+") << z.imag() << "j)";
    return s.str();
}

// `who` names the block in errors. Throws std::invalid_argument naming the parameter.
// `accept_mimo`: a MIMO mask file gives its pilots (the receiving end: pilot_extractor); else it
// is refused, so that a transmitter or a template never drops the file's transmit elements.
// `pilot_symbol`: the block's own, which a mask file's must equal; none for a block that reads
// pilots already divided by the symbol (the maps): then a mask file keeps its own, and explicit
// positions get 1.
inline super_frame_mask block_mask(const std::string& who,
                             int n_symbols,
                             int n_subcarriers,
                             const std::string& mask_file,
                             const std::vector<int>& pilot_positions,
                             std::optional<gr_complex> pilot_symbol,
                             bool accept_mimo = false)
{
    frame_settings fs;
    fs.n_symbols = n_symbols;
    fs.n_subcarriers = n_subcarriers;
    if (n_symbols < 1 || n_subcarriers < 1)
        throw std::invalid_argument(who + ": n_symbols and n_subcarriers must be >= 1, got " +
                                    std::to_string(n_symbols) + " x " + std::to_string(n_subcarriers));
    if (!mask_file.empty() && !pilot_positions.empty())
        throw std::invalid_argument(who + ": give either mask_file or pilot_positions, not both");
    if (mask_file.empty() && pilot_positions.empty())
        throw std::invalid_argument(who + ": no pilots: give mask_file or pilot_positions");

    if (!mask_file.empty()) {
        super_frame_mask mask = [&] {
            try {
                // A MIMO mask file's pilots are its `mask` (every transmit element's together):
                // what the receiving end reads (mimo_pilot_mapper places them per element).
                const auto j = json_read::parse_file(mask_file);
                const auto format = j.is_object() ? j.find("format") : j.end();
                if (format != j.end() && format->is_string() && format->get<std::string>() == mimo_mask::format_name) {
                    const auto m = mimo_mask::from_json(j, mask_file);
                    if (!accept_mimo)
                        throw std::invalid_argument(
                            "'" + mask_file + "' is a MIMO mask (sems.mimo_mask, n_transmit = " +
                            std::to_string(m.n_transmit()) + "); this block takes one pilot mask: a MIMO mask is "
                            "sent by mimo_pilot_mapper and read by pilot_extractor");
                    return super_frame_mask(m.mask());
                }
                return super_frame_mask::load(mask_file);
            } catch (const std::invalid_argument& e) { // the reader names the file and the problem
                throw std::invalid_argument(who + ": mask_file: " + e.what());
            }
        }();
        mask.check_frame(fs, who + " (mask_file '" + mask_file + "')");
        // The file carries its own pilot symbol; a different one on the block would make
        // the two ends of the chain disagree, so it is refused rather than overridden.
        if (pilot_symbol && mask.pilot_symbol() != *pilot_symbol)
            throw std::invalid_argument(who + ": pilot_symbol " + complex_text(*pilot_symbol) +
                                        " differs from the pilot_symbol " +
                                        complex_text(mask.pilot_symbol()) + " of mask_file '" + mask_file +
                                        "'; set them equal");
        return mask;
    }

    const long grid = static_cast<long>(n_symbols) * n_subcarriers;
    std::vector<pilot_position> pos;
    pos.reserve(pilot_positions.size());
    for (size_t i = 0; i < pilot_positions.size(); ++i) {
        const int p = pilot_positions[i];
        if (p < 0 || p >= grid)
            throw std::invalid_argument(who + ": pilot_positions[" + std::to_string(i) + "] = " +
                                        std::to_string(p) + " is outside the " + std::to_string(n_symbols) +
                                        " x " + std::to_string(n_subcarriers) + " grid (flat index n*M+m in [0, " +
                                        std::to_string(grid - 1) + "])");
        pos.push_back({ p / n_subcarriers, p % n_subcarriers });
    }
    return super_frame_mask(pilot_mask(n_symbols, n_subcarriers, std::move(pos), pilot_symbol.value_or(gr_complex(1.0f, 0.0f)),
                                       { { "kind", "explicit" } }, who + " pilot_positions"));
}

// Power parameters are energies per symbol: finite and >= 0.
inline void check_power(const std::string& who, const std::string& name, double value)
{
    if (!checks::non_negative(value))
        throw std::invalid_argument(who + ": " + name + " must be finite and >= 0, got " + std::to_string(value));
}

// The same for a block that reads one frame's pilots (a frame search template, a
// range–Doppler map): a super-frame mask is refused, naming its F.
inline pilot_mask block_mask_one_frame(const std::string& who,
                                       int n_symbols,
                                       int n_subcarriers,
                                       const std::string& mask_file,
                                       const std::vector<int>& pilot_positions,
                                       std::optional<gr_complex> pilot_symbol)
{
    auto mask = block_mask(who, n_symbols, n_subcarriers, mask_file, pilot_positions, pilot_symbol);
    if (mask.n_frames() != 1)
        throw std::invalid_argument(who + ": mask_file '" + mask_file + "' spans a super-frame of F = " +
                                    std::to_string(mask.n_frames()) + " frames, but " + who +
                                    " takes one frame's mask (F = 1)");
    return mask.set(0);
}

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_BLOCK_MASK_H */
