// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems apps: a comma-separated list of whole numbers from a command-line option (batch
 * sizes, thread counts, array sizes), each checked against its range. */
#ifndef INCLUDED_SEMS_APPS_COUNT_LIST_H
#define INCLUDED_SEMS_APPS_COUNT_LIST_H

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace apps {

// The whole numbers of `text` ("1,32,256"), each in [lo, hi]; an empty list, an item that is
// not a whole number or one out of range is refused, naming `option` and the item.
inline std::vector<int> parse_counts(const std::string& text, const std::string& option, int lo = 1,
                                     int hi = 1 << 30)
{
    std::vector<int> out;
    size_t at = 0;
    while (at <= text.size()) {
        const size_t comma = std::min(text.find(',', at), text.size());
        const std::string item = text.substr(at, comma - at);
        size_t used = 0;
        long v = 0;
        try {
            v = std::stol(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (item.empty() || used != item.size() || v < lo || v > hi)
            throw std::invalid_argument(option + ": \"" + item + "\" is not a whole number in " + std::to_string(lo) +
                                        " .. " + std::to_string(hi) + " (comma-separated list)");
        out.push_back(static_cast<int>(v));
        at = comma + 1;
    }
    return out;
}

} // namespace apps
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_APPS_COUNT_LIST_H */
