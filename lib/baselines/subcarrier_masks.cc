// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot patterns for RP- and OP-MUSIC. See subcarrier_masks.h. */
#include "core/kernels/rng.h"
#include <gnuradio/sems/baselines/subcarrier_masks.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {

std::vector<int> spread_rows(int k, int n)
{
    std::vector<int> out(k);
    for (int i = 0; i < k; ++i)
        out[i] = static_cast<int>(std::floor((i + 0.5) * n / k));
    return out;
}

void check(int n_symbols, int n_subcarriers, int count, const std::string& who)
{
    if (n_symbols < 1 || n_subcarriers < 1)
        throw std::invalid_argument(who + ": grid dimensions must be >= 1");
    if (count < 2 || count > n_symbols * n_subcarriers)
        throw std::invalid_argument(who + ": count must be in [2, N*M], got " + std::to_string(count));
}

// Two-level nested array with k elements over [0, m): {0..N1-1} ∪ {(N1+1)j - 1, j = 1..N2},
// N1 + N2 = k, maximising the contiguous co-array (N1+1)·N2 within m.
std::vector<int> nested(int k, int m)
{
    if (k >= m) {
        std::vector<int> all(m);
        std::iota(all.begin(), all.end(), 0);
        return all;
    }
    int best_n1 = k - 1, best_len = -1;
    for (int n1 = 1; n1 < k; ++n1) {
        const int n2 = k - n1, span = (n1 + 1) * n2; // largest position + 1
        if (span <= m && span > best_len) {
            best_len = span;
            best_n1 = n1;
        }
    }
    if (best_len < 0) { // cannot fit: fall back to a contiguous block
        std::vector<int> block(k);
        std::iota(block.begin(), block.end(), 0);
        return block;
    }
    std::vector<int> pos;
    for (int i = 0; i < best_n1; ++i)
        pos.push_back(i);
    for (int j = 1; j <= k - best_n1; ++j)
        pos.push_back((best_n1 + 1) * j - 1);
    std::sort(pos.begin(), pos.end());
    pos.erase(std::unique(pos.begin(), pos.end()), pos.end());
    return pos;
}

} // namespace

pilot_mask random_subcarrier_mask(int n_symbols, int n_subcarriers, int count, uint64_t seed)
{
    const std::string who = "random-subcarrier pilot mask";
    check(n_symbols, n_subcarriers, count, who);
    const auto lattice = pilot_mask::uniform(n_symbols, n_subcarriers, count);
    std::vector<int> per_row(n_symbols, 0);
    for (const auto& p : lattice.positions())
        ++per_row[p.n];
    rng gen(seed);
    std::vector<pilot_position> pilots;
    for (int n = 0; n < n_symbols; ++n) {
        if (per_row[n] == 0)
            continue;
        std::vector<int> cells(n_subcarriers);
        std::iota(cells.begin(), cells.end(), 0);
        for (int i = 0; i < per_row[n]; ++i)
            std::swap(cells[i], cells[i + gen.below(cells.size() - i)]);
        for (int i = 0; i < per_row[n]; ++i)
            pilots.push_back({ n, cells[i] });
    }
    return pilot_mask(n_symbols, n_subcarriers, pilots, { 1.0f, 0.0f },
                      { { "kind", "random_subcarriers" }, { "seed", seed }, { "rows_from", "uniform" } }, who);
}

pilot_mask nested_subcarrier_mask(int n_symbols, int n_subcarriers, int count, int rows)
{
    const std::string who = "nested-subcarrier pilot mask";
    check(n_symbols, n_subcarriers, count, who);
    if (rows < 1 || rows > n_symbols)
        throw std::invalid_argument(who + ": rows must be in [1, N], got " + std::to_string(rows));
    const int per = count / rows, extra = count % rows;
    if (per > n_subcarriers || (extra > 0 && rows + 1 > n_symbols))
        throw std::invalid_argument(who + ": " + std::to_string(count) + " pilots do not fit " +
                                    std::to_string(rows) + " rows of " + std::to_string(n_subcarriers));
    const int used_rows = rows + (extra > 0 ? 1 : 0);
    const auto r = spread_rows(used_rows, n_symbols);
    std::vector<pilot_position> pilots;
    for (int i = 0; i < rows; ++i) {
        auto cols = nested(per, n_subcarriers);
        // Pad (when the nested set is shorter than asked) with the lowest free subcarriers.
        for (int m = 0; static_cast<int>(cols.size()) < per && m < n_subcarriers; ++m)
            if (std::find(cols.begin(), cols.end(), m) == cols.end())
                cols.push_back(m);
        for (int m : cols)
            pilots.push_back({ r[i], m });
    }
    if (extra > 0) {
        auto cols = extra >= 2 ? nested(extra, n_subcarriers) : std::vector<int>{ 0 };
        for (int m = 0; static_cast<int>(cols.size()) < extra && m < n_subcarriers; ++m)
            if (std::find(cols.begin(), cols.end(), m) == cols.end())
                cols.push_back(m);
        for (int m : cols)
            pilots.push_back({ r[rows], m });
    }
    return pilot_mask(n_symbols, n_subcarriers, pilots, { 1.0f, 0.0f },
                      { { "kind", "nested_subcarriers" }, { "rows", rows } }, who);
}

} // namespace sems
} // namespace gr
