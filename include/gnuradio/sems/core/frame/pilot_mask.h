// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The binary N x M pilot mask P and its JSON file format (docs/design.md §2, §4).
 *
 * \details Pilots are kept in mask order: row-major, sorted by (n, m). Every constructor
 * validates (dimensions, range, duplicates, count, pilot energies) and throws
 * std::invalid_argument naming the source and the problem; nothing is clipped or
 * de-duplicated silently.
 *
 * Pilot energy: pilot k carries sqrt(p_k)·s_p, with p_k > 0 and mean(p) = 1 (the total
 * pilot energy of equal power). Its observation Y/x_k (x_k = transmitted_pilot(k)) is H + noise of standard
 * deviation σ/sqrt(p_k): noise_scale() is that rule, and every place that forms pilot
 * observations uses it. Without a `power` list every p_k is 1 (equal power).
 *
 * Pilot phases: pilot k may also carry a phase φ_k, so that it sends sqrt(p_k)·s_p·exp(jφ_k)
 * (transmitted_pilot(), the one accessor every transmitter, extractor and template uses).
 * Equal phases add up coherently in the time domain: K pilots on one OFDM symbol peak at
 * sqrt(K) times their rms, which a converter with full scale at a few times the rms clips.
 * The observation Y/(sqrt(p_k)·s_p·exp(jφ_k)) is H plus circular noise of the same law, so
 * the phases change nothing a decoder sees. Without phases every φ_k is 0 and the
 * transmitted values are bit for bit those of a mask without the key.
 */
#ifndef INCLUDED_SEMS_CORE_PILOT_MASK_H
#define INCLUDED_SEMS_CORE_PILOT_MASK_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief One pilot's resource element. */
struct SEMS_API pilot_position {
    int n; ///< OFDM symbol (slow time)
    int m; ///< subcarrier
    /*! \brief Mask order: row-major by (n, m). \param o the other position. \return true if this comes first. */
    bool operator<(const pilot_position& o) const { return n < o.n || (n == o.n && m < o.m); }
    /*! \brief Equality. \param o the other position. \return true if n and m are equal. */
    bool operator==(const pilot_position& o) const { return n == o.n && m == o.m; }
};

/*!
 * \brief The pilot mask: which resource elements of the N x M frame carry the pilot symbol.
 * \details Pilots are kept in mask order (row-major, sorted by (n, m)); that order is the
 * order of pilot_extractor's output and of the decoders' inputs.
 */
class SEMS_API pilot_mask
{
public:
    static constexpr const char* format_name = "sems.pilot_mask"; ///< the file's `format`
    static constexpr int format_version = 1;                      ///< the file's `version`

    /*!
     * \brief A mask of explicit positions, in any order (stored sorted).
     * \param n_symbols N.
     * \param n_subcarriers M.
     * \param pilots the positions (no duplicates, inside the grid, at least one).
     * \param pilot_symbol s_p, the symbol every pilot carries.
     * \param origin how the mask was made (saved in the file).
     * \param source names the origin in errors.
     * \param power the pilots' relative energies p_k, power[i] for pilots[i] as given
     *        (each > 0 and finite, mean 1 within power_mean_tolerance); empty: all 1.
     * \param phases the pilots' phases φ_k in radians, phases[i] for pilots[i] as given (each
     *        finite); empty: all 0, or the named `phase_sequence`.
     * \param phase_sequence a named phase sequence (phase_sequence_names(), e.g. "newman"),
     *        computed from the sorted positions; empty: `phases` as given. Not both.
     * \throws std::invalid_argument naming `source` and the problem.
     */
    pilot_mask(int n_symbols,
               int n_subcarriers,
               std::vector<pilot_position> pilots,
               gr_complex pilot_symbol = gr_complex(1.0f, 0.0f),
               nlohmann::json origin = { { "kind", "explicit" } },
               const std::string& source = "pilot mask",
               std::vector<double> power = {},
               std::vector<double> phases = {},
               const std::string& phase_sequence = "");

    /*! \brief How far the mean of the `power` list may be from 1 (relative). */
    static constexpr double power_mean_tolerance = 1e-6;

    /*!
     * \brief Uniform lattice: rows and columns evenly spaced, as square as the grid allows.
     * \param n_symbols N. \param n_subcarriers M. \param count N_p, 1..N·M.
     * \return the mask.
     * \throws std::invalid_argument if count is out of range.
     */
    static pilot_mask uniform(int n_symbols, int n_subcarriers, int count);
    /*!
     * \brief Seeded uniform draw without replacement; the same seed gives the same mask.
     * \param n_symbols N. \param n_subcarriers M. \param count N_p, 1..N·M. \param seed the seed.
     * \return the mask.
     * \throws std::invalid_argument if count is out of range.
     */
    static pilot_mask random(int n_symbols, int n_subcarriers, int count, uint64_t seed);
    /*!
     * \brief Doppler-oriented: every symbol of a few evenly spaced subcarriers (long slow-time runs).
     * \param n_symbols N. \param n_subcarriers M. \param count N_p, 1..N·M.
     * \return the mask.
     * \throws std::invalid_argument if count is out of range.
     */
    static pilot_mask doppler(int n_symbols, int n_subcarriers, int count);
    /*!
     * \brief Staggered band edges: every symbol sampled (as in the Doppler pattern), with pilot
     * i in symbol order on column i mod K of K = min(M, 2·⌈N_p/N⌉) subcarriers spread from band edge to
     * band edge, so the pilots also span the band's whole aperture (a body's extent in range).
     * \param n_symbols N. \param n_subcarriers M. \param count N_p, 1..N·M.
     * \return the mask.
     * \throws std::invalid_argument if count is out of range.
     */
    static pilot_mask staggered(int n_symbols, int n_subcarriers, int count);
    /*!
     * \brief Burst: the Doppler pattern's subcarriers, each sampled on a run of consecutive
     * symbols in the middle of the frame instead of spread over it. Below N pilots the slow time
     * is sampled at every symbol (the whole unambiguous Doppler span) for a shorter time; with a
     * multiple of N pilots it is the Doppler pattern.
     * \param n_symbols N. \param n_subcarriers M. \param count N_p, 1..N·M.
     * \return the mask.
     * \throws std::invalid_argument if count is out of range.
     */
    static pilot_mask burst(int n_symbols, int n_subcarriers, int count);
    /*!
     * \brief Builds a mask by pattern name.
     * \param pattern "uniform", "random", "doppler", "staggered" or "burst".
     * \param n_symbols N. \param n_subcarriers M. \param count N_p.
     * \param seed the seed of "random" (ignored by the others).
     * \return the mask.
     * \throws std::invalid_argument on an unknown pattern or a bad count.
     */
    static pilot_mask from_pattern(const std::string& pattern,
                                   int n_symbols,
                                   int n_subcarriers,
                                   int count,
                                   uint64_t seed = 0);

    /*!
     * \brief Builds a mask by pattern name on a frame's usable subcarriers: the pattern is
     *        laid over the N x (M − guards) grid of the non-guard subcarriers, so no pilot
     *        lands on a guard. Without guards it is from_pattern(pattern, N, M, count, seed).
     * \param pattern "uniform", "random", "doppler", "staggered" or "burst".
     * \param fs the frame (N, M and its guard subcarriers).
     * \param count N_p, 1..N·(M − guards).
     * \param seed the seed of "random" (ignored by the others).
     * \return the mask.
     * \throws std::invalid_argument on an unknown pattern, or a count the usable elements cannot hold.
     */
    static pilot_mask
    from_pattern(const std::string& pattern, const frame_settings& fs, int count, uint64_t seed = 0);

    /*!
     * \brief Reads a mask file (docs/reference/file_formats.md).
     * \param path the file.
     * \return the mask.
     * \throws std::invalid_argument naming the file and the problem.
     */
    static pilot_mask load(const std::string& path);
    /*!
     * \brief Parses mask JSON text.
     * \param json_text the JSON. \param source names the text in errors.
     * \return the mask.
     * \throws std::invalid_argument naming `source` and the problem.
     */
    static pilot_mask parse(const std::string& json_text, const std::string& source = "pilot mask text");
    /*!
     * \brief Reads a mask from JSON.
     * \param j the JSON object. \param source names the origin in errors.
     * \return the mask.
     * \throws std::invalid_argument naming `source` and the problem.
     */
    static pilot_mask from_json(const nlohmann::json& j, const std::string& source);
    /*! \brief The file format's JSON. \return the JSON object. */
    nlohmann::json to_json() const;
    /*! \brief The file format's JSON text. \return the text. */
    std::string to_json_string() const;
    /*! \brief Writes the mask file. \param path the file. \throws std::invalid_argument naming the file if it cannot be written. */
    void save(const std::string& path) const;

    /*! \brief N. \return the symbols of the mask's frame. */
    int n_symbols() const { return d_n_symbols; }
    /*! \brief M. \return the subcarriers of the mask's frame. */
    int n_subcarriers() const { return d_n_subcarriers; }
    /*! \brief N_p. \return the number of pilots. */
    int size() const { return static_cast<int>(d_pilots.size()); }
    /*! \brief The pilots. \return the positions in mask order. */
    const std::vector<pilot_position>& positions() const { return d_pilots; }
    /*! \brief s_p. \return the pilot symbol. */
    gr_complex pilot_symbol() const { return d_pilot_symbol; }
    /*!
     * \brief The pilots' relative energies p_k, in mask order (mean 1).
     * \return one value per pilot; all 1 for equal power.
     */
    const std::vector<double>& power() const { return d_power; }
    /*! \brief Whether every pilot has the same energy. \return true if every p_k is 1. */
    bool equal_power() const { return d_equal_power; }
    /*!
     * \brief The pilots' phases φ_k in radians, in mask order.
     * \return one value per pilot; all 0 for a mask without phases.
     */
    const std::vector<double>& phases() const { return d_phases; }
    /*! \brief Whether every pilot's phase is 0. \return true if every φ_k is 0. */
    bool zero_phases() const { return d_zero_phases; }
    /*!
     * \brief The named sequence the phases come from.
     * \return "newman" for Newman phases, empty for an explicit list or no phases.
     */
    const std::string& phase_sequence() const { return d_phase_sequence; }
    /*!
     * \brief The same mask with a named phase sequence.
     * \param sequence "newman" (newman_phases() on each symbol's pilots) or "zero" (no phases).
     * \param source names the caller in errors.
     * \return the mask with those phases (positions, energies and origin unchanged).
     * \throws std::invalid_argument naming `source` on an unknown sequence.
     */
    pilot_mask with_phases(const std::string& sequence, const std::string& source = "pilot phases") const;
    /*!
     * \brief The same mask with explicit phases.
     * \param phases φ_k in radians, in mask order (one per pilot, each finite).
     * \param source names the caller in errors.
     * \return the mask with those phases.
     * \throws std::invalid_argument naming `source` on a wrong length or a non-finite phase.
     */
    pilot_mask with_phases(std::vector<double> phases, const std::string& source = "pilot phases") const;
    /*! \brief The named phase sequences. \return their names ("newman"). */
    static std::vector<std::string> phase_sequence_names();
    /*!
     * \brief Newman's phases for K tones: φ_i = π·i²/K, i = 0..K−1.
     * \details The quadratic (chirp) phase spreads the K tones' energy over the symbol
     * instead of adding them up at one instant. On K adjacent subcarriers its crest factor
     * (peak over rms of the time-domain symbol) is about 1.35, and exactly 1 at the sample
     * instants when K = M is even (the sequence is then a Zadoff–Chu sequence of root 1, whose
     * DFT has constant modulus), against sqrt(K) for equal phases. The mask applies it to each
     * symbol's pilots in subcarrier order; on the 32 random subcarriers of the shipped
     * one-symbol delay mask the crest factor is 2.23 at the 64 samples (2.68 between them)
     * against sqrt(32) = 5.66. Chosen over a Zadoff–Chu sequence of another root because it
     * is defined for every K (odd or even) and has no parameter to pick.
     * \param count K ≥ 1.
     * \return the K phases in radians.
     */
    static std::vector<double> newman_phases(int count);
    /*!
     * \brief The transmitted symbol of pilot k: the one value every transmitter sends and
     *        every receiver divides by.
     * \param k the pilot, in mask order (0..N_p-1).
     * \return sqrt(p_k)·s_p·exp(jφ_k) (exactly sqrt(p_k)·s_p when φ_k = 0).
     */
    gr_complex transmitted_pilot(int k) const;
    /*!
     * \brief The observation noise of pilot k relative to an equal-power pilot.
     * \details The observation Y/x_k = H + W/sqrt(p_k) (x_k = transmitted_pilot(k)): its noise standard
     * deviation is σ·noise_scale(k). Exactly 1 for an equal-power mask.
     * \param k the pilot, in mask order (0..N_p-1).
     * \return 1/sqrt(p_k).
     */
    double noise_scale(int k) const { return noise_scale_of_power(d_power[k]); }
    /*!
     * \brief The rule behind noise_scale(): noise standard deviation relative to an
     *        equal-power pilot, for a pilot of relative energy p.
     * \param p the relative energy (> 0).
     * \return 1/sqrt(p) (exactly 1 for p = 1).
     */
    static double noise_scale_of_power(double p) { return p == 1.0 ? 1.0 : 1.0 / std::sqrt(p); }
    /*! \brief How the mask was made. \return the origin JSON. */
    const nlohmann::json& origin() const { return d_origin; }

    /*! \brief Flat indices. \return n·M + m for each pilot, in mask order. */
    std::vector<int> flat_indices() const;
    /*! \brief The dense mask. \return the 0/1 grid, row-major N x M. */
    std::vector<uint8_t> dense() const;
    /*!
     * \brief Per-symbol pilot subcarrier lists, as gr-digital's ofdm_carrier_allocator_cvc
     *        takes them (pilot_carriers).
     * \return one list of subcarriers per symbol.
     */
    std::vector<std::vector<int>> carrier_lists() const;
    /*!
     * \brief Per-symbol transmitted pilot symbols sqrt(p_k)·s_p·exp(jφ_k) (transmitted_pilot();
     *        ofdm_carrier_allocator_cvc's pilot_symbols).
     * \return one list per symbol.
     */
    std::vector<std::vector<gr_complex>> pilot_symbol_lists() const;

    /*!
     * \brief Checks that the mask fits a frame: the same N x M, and no pilot on a guard subcarrier.
     * \param fs the frame. \param who names the caller in errors.
     * \throws std::invalid_argument naming `who` when the mask does not fit the frame (the
     *         pilot and the guard subcarrier it sits on).
     */
    void check_frame(const frame_settings& fs, const std::string& who) const;

    /*! \brief Equality of grid, positions, pilot symbol, energies and phases. \param o the other mask. \return true if equal. */
    bool operator==(const pilot_mask& o) const;

private:
    int d_n_symbols;
    int d_n_subcarriers;
    std::vector<pilot_position> d_pilots;
    gr_complex d_pilot_symbol;
    nlohmann::json d_origin;
    std::vector<double> d_power;
    bool d_equal_power = true;
    std::vector<double> d_phases;     // φ_k, mask order
    std::vector<gr_complex> d_values; // transmitted_pilot(k), mask order
    bool d_zero_phases = true;
    std::string d_phase_sequence;     // "newman", or empty (explicit list or none)
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_PILOT_MASK_H */
