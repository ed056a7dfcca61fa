// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the binary N x M pilot mask P and its JSON file format (DESIGN §2, §4).
 *
 * Pilots are kept in mask order: row-major, sorted by (n, m). Every constructor
 * validates (dimensions, range, duplicates, count) and throws std::invalid_argument
 * naming the source and the problem; nothing is clipped or de-duplicated silently.
 */
#ifndef INCLUDED_SEMS_CORE_PILOT_MASK_H
#define INCLUDED_SEMS_CORE_PILOT_MASK_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

struct SEMS_API pilot_position {
    int n; // OFDM symbol (slow time)
    int m; // subcarrier
    bool operator<(const pilot_position& o) const { return n < o.n || (n == o.n && m < o.m); }
    bool operator==(const pilot_position& o) const { return n == o.n && m == o.m; }
};

class SEMS_API pilot_mask
{
public:
    static constexpr const char* format_name = "sems.pilot_mask";
    static constexpr int format_version = 1;

    // Explicit positions, in any order (stored sorted). `source` names the origin in errors.
    pilot_mask(int n_symbols,
               int n_subcarriers,
               std::vector<pilot_position> pilots,
               gr_complex pilot_symbol = gr_complex(1.0f, 0.0f),
               nlohmann::json origin = { { "kind", "explicit" } },
               const std::string& source = "pilot mask");

    // Standard patterns.
    // Uniform lattice: rows and columns evenly spaced, as square as the grid allows.
    static pilot_mask uniform(int n_symbols, int n_subcarriers, int count);
    // Seeded uniform draw without replacement; the same seed gives the same mask.
    static pilot_mask random(int n_symbols, int n_subcarriers, int count, uint64_t seed);
    // Doppler-oriented: every symbol of a few evenly spaced subcarriers (long slow-time runs).
    static pilot_mask doppler(int n_symbols, int n_subcarriers, int count);
    // Build by pattern name: "uniform", "random", "doppler".
    static pilot_mask from_pattern(const std::string& pattern,
                                   int n_symbols,
                                   int n_subcarriers,
                                   int count,
                                   uint64_t seed = 0);

    // File format.
    static pilot_mask load(const std::string& path);
    static pilot_mask parse(const std::string& json_text, const std::string& source = "pilot mask text");
    static pilot_mask from_json(const nlohmann::json& j, const std::string& source);
    nlohmann::json to_json() const;
    std::string to_json_string() const;
    void save(const std::string& path) const;

    int n_symbols() const { return d_n_symbols; }
    int n_subcarriers() const { return d_n_subcarriers; }
    int size() const { return static_cast<int>(d_pilots.size()); } // N_p
    const std::vector<pilot_position>& positions() const { return d_pilots; }
    gr_complex pilot_symbol() const { return d_pilot_symbol; }
    const nlohmann::json& origin() const { return d_origin; }

    // n * M + m for each pilot, in mask order.
    std::vector<int> flat_indices() const;
    // Dense 0/1 grid, row-major N x M.
    std::vector<uint8_t> dense() const;
    // Per-symbol pilot subcarrier lists and symbols, as gr-digital's
    // ofdm_carrier_allocator_cvc takes them (pilot_carriers, pilot_symbols).
    std::vector<std::vector<int>> carrier_lists() const;
    std::vector<std::vector<gr_complex>> pilot_symbol_lists() const;

    // Throws std::invalid_argument, naming `who`, when the mask does not fit the frame.
    void check_frame(const frame_settings& fs, const std::string& who) const;

    bool operator==(const pilot_mask& o) const;

private:
    int d_n_symbols;
    int d_n_subcarriers;
    std::vector<pilot_position> d_pilots;
    gr_complex d_pilot_symbol;
    nlohmann::json d_origin;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_PILOT_MASK_H */
