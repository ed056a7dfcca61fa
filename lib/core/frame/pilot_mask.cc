// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot mask validation, standard patterns and the JSON file format. */
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include "core/kernels/rng.h"
#include "core/common/checks.h"
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace gr {
namespace sems {

namespace {

void check_dims(int n_symbols, int n_subcarriers, const std::string& source)
{
    if (n_symbols < 1 || n_symbols > limits::max_symbols)
        json_read::fail(source, "n_symbols",
                        "must be in [1, " + std::to_string(limits::max_symbols) + "], got " + std::to_string(n_symbols));
    if (n_subcarriers < 1 || n_subcarriers > limits::max_subcarriers)
        json_read::fail(source, "n_subcarriers",
                        "must be in [1, " + std::to_string(limits::max_subcarriers) + "], got " +
                            std::to_string(n_subcarriers));
    const long long grid = static_cast<long long>(n_symbols) * n_subcarriers;
    if (grid > limits::max_grid)
        json_read::fail(source, "n_symbols * n_subcarriers",
                        "the grid of " + std::to_string(grid) + " resource elements exceeds the limit of " +
                            std::to_string(limits::max_grid));
}

void check_count(int n_symbols, int n_subcarriers, int count, const std::string& source)
{
    check_dims(n_symbols, n_subcarriers, source);
    if (count < 1 || count > n_symbols * n_subcarriers)
        json_read::fail(source, "pilots", "count must be in [1, N*M = " + std::to_string(n_symbols * n_subcarriers) +
                                              "], got " + std::to_string(count));
}

// `k` indices spread evenly over [0, n): the centres of k equal cells.
std::vector<int> spread(int k, int n)
{
    std::vector<int> out(k);
    for (int i = 0; i < k; ++i)
        out[i] = static_cast<int>(std::floor((i + 0.5) * n / k));
    return out;
}

// The Doppler pattern's layout: k = ⌈count/N⌉ subcarriers spread evenly over the band, the
// first count mod k of them with one pilot more, column j's symbols from symbols(pilots in it).
template <class Symbols>
std::vector<pilot_position> doppler_columns(int n_symbols, int n_subcarriers, int count, Symbols symbols)
{
    const int k = (count + n_symbols - 1) / n_symbols;
    std::vector<pilot_position> pilots;
    const auto cols = spread(k, n_subcarriers);
    for (int j = 0; j < k; ++j)
        for (int r : symbols(count / k + (j < count % k ? 1 : 0)))
            pilots.push_back({ r, cols[j] });
    return pilots;
}

// The pilots' energies: one per pilot, each finite and > 0 (a pilot of zero energy
// observes nothing: its observation Y/(sqrt(p)·s_p) is undefined), mean 1.
void check_power(const std::vector<double>& power, size_t n_pilots, const std::string& source)
{
    if (power.size() != n_pilots)
        json_read::fail(source, "power",
                        "lists " + std::to_string(power.size()) + " energies for " + std::to_string(n_pilots) +
                            " pilots (one per pilot, in the order of the pilot list)");
    bool all_zero = true;
    for (size_t i = 0; i < power.size(); ++i) {
        const std::string field = "power[" + std::to_string(i) + "]";
        if (!std::isfinite(power[i]))
            json_read::fail(source, field, "must be finite, got " + std::to_string(power[i]));
        if (power[i] < 0.0)
            json_read::fail(source, field, "must not be negative, got " + std::to_string(power[i]));
        all_zero = all_zero && power[i] == 0.0;
    }
    if (all_zero)
        json_read::fail(source, "power", "every pilot has zero energy");
    for (size_t i = 0; i < power.size(); ++i)
        if (power[i] == 0.0)
            json_read::fail(source, "power[" + std::to_string(i) + "]",
                            "is 0: every pilot needs energy > 0 (a pilot without energy observes nothing)");
    const double mean = std::accumulate(power.begin(), power.end(), 0.0) / double(power.size());
    if (!(std::fabs(mean - 1.0) <= pilot_mask::power_mean_tolerance))
        json_read::fail(source, "power",
                        "the mean is " + std::to_string(mean) +
                            ", must be 1 (the total pilot energy of equal power) within a relative " +
                            std::to_string(pilot_mask::power_mean_tolerance));
}

// The named phase sequences as a message lists them: "newman, ...".
std::string sequence_list()
{
    std::string out;
    for (const auto& name : pilot_mask::phase_sequence_names())
        out += (out.empty() ? "" : ", ") + name;
    return out;
}

// The phases as given: one per pilot, each finite.
void check_phases(const std::vector<double>& phases, size_t n_pilots, const std::string& source)
{
    if (phases.size() != n_pilots)
        json_read::fail(source, "phases",
                        "lists " + std::to_string(phases.size()) + " phases for " + std::to_string(n_pilots) +
                            " pilots (one per pilot in radians, in the order of the pilot list)");
    for (size_t i = 0; i < phases.size(); ++i)
        if (!std::isfinite(phases[i]))
            json_read::fail(source, "phases[" + std::to_string(i) + "]",
                            "must be a finite number of radians, got " + std::to_string(phases[i]));
}

} // namespace

pilot_mask::pilot_mask(int n_symbols,
                       int n_subcarriers,
                       std::vector<pilot_position> pilots,
                       gr_complex pilot_symbol,
                       nlohmann::json origin,
                       const std::string& source,
                       std::vector<double> power,
                       std::vector<double> phases,
                       const std::string& phase_sequence)
    : d_n_symbols(n_symbols),
      d_n_subcarriers(n_subcarriers),
      d_pilots(std::move(pilots)),
      d_pilot_symbol(pilot_symbol),
      d_origin(std::move(origin)),
      d_phase_sequence(phase_sequence)
{
    check_dims(n_symbols, n_subcarriers, source);
    if (d_pilots.empty())
        json_read::fail(source, "pilots", "a mask needs at least one pilot");
    if (!power.empty())
        check_power(power, d_pilots.size(), source);
    if (!phases.empty() && !phase_sequence.empty())
        json_read::fail(source, "phases", "give a list of phases or a sequence name, not both");
    if (!phases.empty())
        check_phases(phases, d_pilots.size(), source);
    if (!phase_sequence.empty()) {
        const auto known = phase_sequence_names();
        if (std::find(known.begin(), known.end(), phase_sequence) == known.end())
            json_read::fail(source, "phases",
                            "unknown phase sequence \"" + phase_sequence +
                                "\" (known: " + sequence_list() + "; or a list of one phase in radians per pilot)");
    }
    // Energies and phases, given in the order of the pilot list, sorted into mask order
    // together with the positions.
    std::vector<size_t> order(d_pilots.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return d_pilots[a] < d_pilots[b]; });
    d_power.assign(d_pilots.size(), 1.0);
    d_phases.assign(d_pilots.size(), 0.0);
    for (size_t i = 0; i < order.size(); ++i) {
        if (!power.empty())
            d_power[i] = power[order[i]];
        if (!phases.empty())
            d_phases[i] = phases[order[i]];
    }
    d_equal_power = std::all_of(d_power.begin(), d_power.end(), [](double p) { return p == 1.0; });
    for (const auto& p : d_pilots)
        if (p.n < 0 || p.n >= n_symbols || p.m < 0 || p.m >= n_subcarriers)
            json_read::fail(source, "pilots",
                            "position [" + std::to_string(p.n) + ", " + std::to_string(p.m) +
                                "] is outside the " + std::to_string(n_symbols) + " x " +
                                std::to_string(n_subcarriers) + " grid");
    std::sort(d_pilots.begin(), d_pilots.end());
    auto dup = std::adjacent_find(d_pilots.begin(), d_pilots.end());
    if (dup != d_pilots.end())
        json_read::fail(source, "pilots",
                        "duplicate position [" + std::to_string(dup->n) + ", " + std::to_string(dup->m) + "]");
    if (!checks::finite(pilot_symbol) ||
        std::norm(pilot_symbol) == 0.0f)
        json_read::fail(source, "pilot_symbol", "must be finite and non-zero (observations are divided by it)");
    if (!d_origin.is_object())
        json_read::fail(source, "origin", "expected a JSON object");
    if (phase_sequence == "newman") // each symbol's pilots, in subcarrier order (mask order is row-major)
        for (size_t first = 0; first < d_pilots.size();) {
            size_t last = first;
            while (last < d_pilots.size() && d_pilots[last].n == d_pilots[first].n)
                ++last;
            const auto row = newman_phases(static_cast<int>(last - first));
            std::copy(row.begin(), row.end(), d_phases.begin() + static_cast<std::ptrdiff_t>(first));
            first = last;
        }
    d_zero_phases = std::all_of(d_phases.begin(), d_phases.end(), [](double f) { return f == 0.0; });
    // The transmitted values, once: sqrt(p_k)·s_p, rotated by exp(jφ_k) only where φ_k ≠ 0,
    // so a mask without phases sends the same bits as before phases existed.
    d_values.resize(d_pilots.size());
    for (size_t k = 0; k < d_pilots.size(); ++k) {
        const double p = d_power[k];
        const gr_complex v = p == 1.0 ? d_pilot_symbol : d_pilot_symbol * static_cast<float>(std::sqrt(p));
        d_values[k] = d_phases[k] == 0.0
                          ? v
                          : gr_complex(std::complex<double>(v) * std::polar(1.0, d_phases[k]));
    }
}

std::vector<std::string> pilot_mask::phase_sequence_names() { return { "newman" }; }

std::vector<double> pilot_mask::newman_phases(int count)
{
    if (count < 1)
        throw std::invalid_argument("newman_phases: count must be >= 1, got " + std::to_string(count));
    std::vector<double> out(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) // π·i²/K, i² exact in double for every K the grid allows
        out[static_cast<size_t>(i)] = M_PI * (double(i) * double(i)) / double(count);
    return out;
}

pilot_mask pilot_mask::with_phases(const std::string& sequence, const std::string& source) const
{
    if (sequence == "zero")
        return pilot_mask(d_n_symbols, d_n_subcarriers, d_pilots, d_pilot_symbol, d_origin, source, d_power);
    if (sequence.empty())
        json_read::fail(source, "phases", "no sequence named (known: " + sequence_list() + ", zero)");
    return pilot_mask(d_n_symbols, d_n_subcarriers, d_pilots, d_pilot_symbol, d_origin, source, d_power, {},
                      sequence);
}

pilot_mask pilot_mask::with_phases(std::vector<double> phases, const std::string& source) const
{
    if (phases.empty()) // an empty list would read as "no phases": say what is missing instead
        json_read::fail(source, "phases",
                        "lists 0 phases for " + std::to_string(size()) + " pilots (one per pilot in radians)");
    return pilot_mask(d_n_symbols, d_n_subcarriers, d_pilots, d_pilot_symbol, d_origin, source, d_power,
                      std::move(phases));
}

pilot_mask pilot_mask::uniform(int n_symbols, int n_subcarriers, int count)
{
    check_count(n_symbols, n_subcarriers, count, "uniform pilot mask");
    // Pick a rows x b columns (a·b >= count, the last row possibly partial) whose
    // spacings N/a and M/b are as equal as possible, preferring no spare cells.
    int best_a = 1;
    double best_score = std::numeric_limits<double>::infinity();
    for (int a = 1; a <= std::min(n_symbols, count); ++a) {
        const int b = (count + a - 1) / a;
        if (b > n_subcarriers)
            continue;
        const double aspect = std::fabs(std::log((double(n_symbols) / a) / (double(n_subcarriers) / b)));
        const double spare = double(a * b - count) / count;
        const double score = aspect + spare;
        if (score < best_score - 1e-12) {
            best_score = score;
            best_a = a;
        }
    }
    const int a = best_a, b = (count + a - 1) / a;
    std::vector<pilot_position> pilots;
    const auto rows = spread(a, n_symbols);
    for (int i = 0; i < a; ++i) {
        const int in_row = std::min(b, count - i * b);
        for (int c : spread(in_row, n_subcarriers))
            pilots.push_back({ rows[i], c });
    }
    return pilot_mask(n_symbols, n_subcarriers, pilots, { 1.0f, 0.0f },
                      { { "kind", "uniform" }, { "rows", a }, { "columns", b } }, "uniform pilot mask");
}

pilot_mask pilot_mask::random(int n_symbols, int n_subcarriers, int count, uint64_t seed)
{
    check_count(n_symbols, n_subcarriers, count, "random pilot mask");
    // Partial Fisher–Yates over the flat grid with the project's portable generator.
    std::vector<int> cells(n_symbols * n_subcarriers);
    std::iota(cells.begin(), cells.end(), 0);
    rng gen(seed);
    for (int i = 0; i < count; ++i)
        std::swap(cells[i], cells[i + gen.below(cells.size() - i)]);
    std::vector<pilot_position> pilots;
    for (int i = 0; i < count; ++i)
        pilots.push_back({ cells[i] / n_subcarriers, cells[i] % n_subcarriers });
    return pilot_mask(n_symbols, n_subcarriers, pilots, { 1.0f, 0.0f },
                      { { "kind", "random" }, { "seed", seed } }, "random pilot mask");
}

pilot_mask pilot_mask::doppler(int n_symbols, int n_subcarriers, int count)
{
    check_count(n_symbols, n_subcarriers, count, "doppler pilot mask");
    // As few subcarriers as the count allows, each sampled over (nearly) every symbol:
    // the longest slow-time runs give the finest Doppler resolution.
    const int k = (count + n_symbols - 1) / n_symbols;
    return pilot_mask(n_symbols, n_subcarriers,
                      doppler_columns(n_symbols, n_subcarriers, count, [&](int in_col) { return spread(in_col, n_symbols); }),
                      { 1.0f, 0.0f }, { { "kind", "doppler" }, { "subcarriers", k } }, "doppler pilot mask");
}

pilot_mask pilot_mask::staggered(int n_symbols, int n_subcarriers, int count)
{
    check_count(n_symbols, n_subcarriers, count, "staggered pilot mask");
    // Every symbol (or, below N pilots, evenly spread symbols) carries its share of the pilots,
    // and pilot i in symbol order sits on column i mod K of K subcarriers spread from band edge
    // to band edge, K twice the subcarriers the Doppler pattern would use: slow time is sampled
    // at every symbol, as with the Doppler pattern, while the pilots span the whole band, whose
    // aperture resolves a body's extent in range.
    const int per_col = (count + n_symbols - 1) / n_symbols;
    const int k = std::min(n_subcarriers, 2 * per_col);
    std::vector<int> cols(k);
    for (int j = 0; j < k; ++j)
        cols[j] = k == 1 ? 0 : static_cast<int>(std::lround(double(j) * (n_subcarriers - 1) / (k - 1)));
    std::vector<int> per_symbol(n_symbols, count / n_symbols);
    for (int r : spread(count % n_symbols, n_symbols))
        ++per_symbol[r];
    std::vector<pilot_position> pilots;
    int i = 0;
    for (int n = 0; n < n_symbols; ++n)
        for (int t = 0; t < per_symbol[n]; ++t, ++i)
            pilots.push_back({ n, cols[i % k] });
    return pilot_mask(n_symbols, n_subcarriers, pilots, { 1.0f, 0.0f },
                      { { "kind", "staggered" }, { "subcarriers", k } }, "staggered pilot mask");
}

pilot_mask pilot_mask::burst(int n_symbols, int n_subcarriers, int count)
{
    check_count(n_symbols, n_subcarriers, count, "burst pilot mask");
    // The Doppler pattern's subcarriers and counts, each on consecutive symbols centred in the
    // frame: every symbol's slow time (Doppler unambiguous over ±1/(2T)) for a shorter time.
    const int k = (count + n_symbols - 1) / n_symbols;
    const auto run = [&](int in_col) {
        std::vector<int> rows(in_col);
        std::iota(rows.begin(), rows.end(), (n_symbols - in_col) / 2);
        return rows;
    };
    return pilot_mask(n_symbols, n_subcarriers, doppler_columns(n_symbols, n_subcarriers, count, run), { 1.0f, 0.0f },
                      { { "kind", "burst" }, { "subcarriers", k } }, "burst pilot mask");
}

pilot_mask pilot_mask::from_pattern(
    const std::string& pattern, int n_symbols, int n_subcarriers, int count, uint64_t seed)
{
    if (pattern == "uniform")
        return uniform(n_symbols, n_subcarriers, count);
    if (pattern == "random")
        return random(n_symbols, n_subcarriers, count, seed);
    if (pattern == "doppler")
        return doppler(n_symbols, n_subcarriers, count);
    if (pattern == "staggered")
        return staggered(n_symbols, n_subcarriers, count);
    if (pattern == "burst")
        return burst(n_symbols, n_subcarriers, count);
    throw std::invalid_argument("unknown pilot pattern \"" + pattern +
                                "\" (known: uniform, random, doppler, staggered, burst)");
}

pilot_mask pilot_mask::from_pattern(const std::string& pattern, const frame_settings& fs, int count, uint64_t seed)
{
    if (fs.guard_subcarriers.empty())
        return from_pattern(pattern, fs.n_symbols, fs.n_subcarriers, count, seed);
    fs.validate();
    const auto usable = fs.usable_subcarriers();
    const int u = static_cast<int>(usable.size());
    if (count < 1 || count > fs.usable_elements())
        throw std::invalid_argument(pattern + " pilot mask: N_p = " + std::to_string(count) +
                                    " pilots do not fit the N*(M - guards) = " + std::to_string(fs.n_symbols) + "*" +
                                    std::to_string(u) + " = " + std::to_string(fs.usable_elements()) +
                                    " usable resource elements of the frame");
    // The pattern on the grid of usable subcarriers, its columns mapped back to the frame's.
    const auto packed = from_pattern(pattern, fs.n_symbols, u, count, seed);
    std::vector<pilot_position> pilots;
    pilots.reserve(packed.positions().size());
    for (const auto& p : packed.positions())
        pilots.push_back({ p.n, usable[static_cast<size_t>(p.m)] });
    auto origin = packed.origin();
    origin["guard_subcarriers"] = static_cast<int>(fs.guard_subcarriers.size());
    return pilot_mask(fs.n_symbols, fs.n_subcarriers, std::move(pilots), packed.pilot_symbol(), origin,
                      pattern + " pilot mask");
}

pilot_mask pilot_mask::from_json(const nlohmann::json& j, const std::string& source)
{
    using namespace json_read;
    check_format(j, format_name, format_version, source);
    if (j.contains("frames"))
        fail(source, "frames",
             "a super-frame mask (a pilot set per frame) where one frame's mask is read: give a mask of one "
             "frame, or read the file as a super-frame mask (super_frame_mask)");
    object_reader r(j, source);
    r.allow("format");
    r.allow("version");
    const int n_sym = r.int_required("n_symbols", 1, limits::max_symbols);
    const int n_sub = r.int_required("n_subcarriers", 1, limits::max_subcarriers);
    check_dims(n_sym, n_sub, source);

    gr_complex symbol(1.0f, 0.0f);
    if (const auto* ps = r.find("pilot_symbol")) {
        if (!ps->is_array() || ps->size() != 2)
            fail(source, "pilot_symbol", "expected [re, im]");
        symbol = gr_complex(to_float(finite_number((*ps)[0], "pilot_symbol[0]", source), "pilot_symbol[0]", source),
                            to_float(finite_number((*ps)[1], "pilot_symbol[1]", source), "pilot_symbol[1]", source));
    }

    const long long grid = static_cast<long long>(n_sym) * n_sub;
    const auto& list = r.require("pilots");
    if (!list.is_array())
        fail(source, "pilots", "expected a list of [n, m] pairs");
    if (static_cast<long long>(list.size()) > grid)
        fail(source, "pilots", "lists " + std::to_string(list.size()) + " pilots, more than the N*M = " +
                                   std::to_string(grid) + " cells of the grid");
    std::vector<pilot_position> pilots;
    pilots.reserve(list.size());
    for (size_t i = 0; i < list.size(); ++i) {
        const auto& p = list[i];
        const std::string field = "pilots[" + std::to_string(i) + "]";
        if (!p.is_array() || p.size() != 2)
            fail(source, field, "expected [n, m], got " + object_reader::short_dump(p));
        // Range-checked as 64-bit integers before the cast: [4294967296, 5] must not become [0, 5].
        const long long n = integer(p[0], field, source), m = integer(p[1], field, source);
        if (n < 0 || n >= n_sym || m < 0 || m >= n_sub)
            fail(source, field,
                 "position [" + std::to_string(n) + ", " + std::to_string(m) + "] is outside the " +
                     std::to_string(n_sym) + " x " + std::to_string(n_sub) + " grid");
        pilots.push_back({ static_cast<int>(n), static_cast<int>(m) });
    }
    if (const auto* np = r.find("n_pilots")) {
        const auto declared = integer(*np, "n_pilots", source);
        if (declared != static_cast<long long>(pilots.size()))
            fail(source, "n_pilots",
                 "declares " + std::to_string(declared) + " pilots but the list has " + std::to_string(pilots.size()));
    }
    // power: optional, one relative energy per pilot of the list (absent: all 1).
    std::vector<double> power;
    if (const auto* pw = r.find("power")) {
        if (!pw->is_array())
            fail(source, "power", "expected a list of one energy per pilot, got " + object_reader::short_dump(*pw));
        if (pw->size() != pilots.size())
            fail(source, "power",
                 "lists " + std::to_string(pw->size()) + " energies for " + std::to_string(pilots.size()) +
                     " pilots (one per pilot, in the order of the pilot list)");
        for (size_t i = 0; i < pw->size(); ++i)
            power.push_back(finite_number((*pw)[i], "power[" + std::to_string(i) + "]", source));
    }
    // phases: optional, a sequence name or one phase in radians per pilot of the list (absent: all 0).
    std::vector<double> phases;
    std::string phase_sequence;
    if (const auto* ph = r.find("phases")) {
        if (ph->is_string() && !ph->get<std::string>().empty()) { // the name is checked with the positions
            phase_sequence = ph->get<std::string>();
        } else if (ph->is_array() && !ph->empty()) { // the length is checked with the positions
            for (size_t i = 0; i < ph->size(); ++i)
                phases.push_back(finite_number((*ph)[i], "phases[" + std::to_string(i) + "]", source));
        } else {
            fail(source, "phases",
                 "expected a sequence name (\"newman\") or a list of one phase in radians per pilot, got " +
                     object_reader::short_dump(*ph));
        }
    }
    // origin: free-form provenance (how the mask was made), kept as written.
    const auto* o = r.find("origin");
    nlohmann::json origin = o ? *o : nlohmann::json{ { "kind", "explicit" } };
    r.finish();
    return pilot_mask(n_sym, n_sub, std::move(pilots), symbol, origin, source, std::move(power), std::move(phases),
                      phase_sequence);
}

pilot_mask pilot_mask::load(const std::string& path) { return from_json(json_read::parse_file(path), path); }

pilot_mask pilot_mask::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

nlohmann::json pilot_mask::to_json() const
{
    nlohmann::json pilots = nlohmann::json::array();
    for (const auto& p : d_pilots)
        pilots.push_back({ p.n, p.m });
    nlohmann::json j = { { "format", format_name },
                         { "version", format_version },
                         { "n_symbols", d_n_symbols },
                         { "n_subcarriers", d_n_subcarriers },
                         { "n_pilots", size() },
                         { "pilot_symbol", { d_pilot_symbol.real(), d_pilot_symbol.imag() } },
                         { "pilots", pilots },
                         { "origin", d_origin } };
    if (!d_equal_power) // equal-power files stay as they were
        j["power"] = d_power;
    if (!d_phase_sequence.empty()) // files without phases stay as they were too
        j["phases"] = d_phase_sequence;
    else if (!d_zero_phases)
        j["phases"] = d_phases;
    return j;
}

gr_complex pilot_mask::transmitted_pilot(int k) const { return d_values.at(static_cast<size_t>(k)); }

std::string pilot_mask::to_json_string() const { return to_json().dump(); }

void pilot_mask::save(const std::string& path) const { json_read::write_file(path, to_json()); }

std::vector<int> pilot_mask::flat_indices() const
{
    std::vector<int> out;
    out.reserve(d_pilots.size());
    for (const auto& p : d_pilots)
        out.push_back(p.n * d_n_subcarriers + p.m);
    return out;
}

std::vector<uint8_t> pilot_mask::dense() const
{
    std::vector<uint8_t> grid(size_t(d_n_symbols) * d_n_subcarriers, 0);
    for (int idx : flat_indices())
        grid[idx] = 1;
    return grid;
}

std::vector<std::vector<int>> pilot_mask::carrier_lists() const
{
    std::vector<std::vector<int>> lists(d_n_symbols);
    for (const auto& p : d_pilots)
        lists[p.n].push_back(p.m);
    return lists;
}

std::vector<std::vector<gr_complex>> pilot_mask::pilot_symbol_lists() const
{
    std::vector<std::vector<gr_complex>> lists(d_n_symbols);
    for (size_t k = 0; k < d_pilots.size(); ++k)
        lists[d_pilots[k].n].push_back(transmitted_pilot(static_cast<int>(k)));
    return lists;
}

void pilot_mask::check_frame(const frame_settings& fs, const std::string& who) const
{
    if (fs.n_symbols != d_n_symbols || fs.n_subcarriers != d_n_subcarriers) {
        // Every field that differs, by name, with both values.
        std::string fields;
        for (const auto& [name, mine, theirs] :
             { std::tuple<const char*, int, int>{ "n_symbols", d_n_symbols, fs.n_symbols },
               { "n_subcarriers", d_n_subcarriers, fs.n_subcarriers } })
            if (mine != theirs)
                fields += std::string(fields.empty() ? "" : "; ") + name + ": the mask has " + std::to_string(mine) +
                          ", the frame has " + std::to_string(theirs);
        throw std::invalid_argument(who + ": the pilot mask is " + std::to_string(d_n_symbols) + " x " +
                                    std::to_string(d_n_subcarriers) + " but the frame is " +
                                    std::to_string(fs.n_symbols) + " x " + std::to_string(fs.n_subcarriers) + " (" +
                                    fields + ")");
    }
    for (size_t i = 0; i < d_pilots.size(); ++i)
        if (fs.is_guard(d_pilots[i].m))
            throw std::invalid_argument(who + ": pilot " + std::to_string(i) + " at [" +
                                        std::to_string(d_pilots[i].n) + ", " + std::to_string(d_pilots[i].m) +
                                        "] is on guard subcarrier " + std::to_string(d_pilots[i].m) +
                                        " of the frame");
}

bool pilot_mask::operator==(const pilot_mask& o) const
{
    return d_n_symbols == o.d_n_symbols && d_n_subcarriers == o.d_n_subcarriers && d_pilots == o.d_pilots &&
           d_pilot_symbol == o.d_pilot_symbol && d_power == o.d_power && d_phases == o.d_phases;
}

} // namespace sems
} // namespace gr
