// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: "log once per kind" for faults caught inside a block's work() (internal).
 *
 * A block never lets an exception escape work() (GNU Radio would end its thread and
 * the flowgraph would hang); it counts the frame it was working on as faulted and
 * reports the first fault of each kind (where + exception type) with its logger.
 */
#ifndef INCLUDED_SEMS_FAULT_LOG_H
#define INCLUDED_SEMS_FAULT_LOG_H

#include <exception>
#include <string>
#include <typeinfo>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

class fault_log
{
public:
    // The kind of `e` raised in `where`; true the first time this kind is seen.
    bool first(const char* where, const std::exception& e)
    {
        const std::string kind = std::string(where) + " (" + typeid(e).name() + ")";
        for (const auto& k : d_kinds)
            if (k == kind)
                return false;
        d_kinds.push_back(kind);
        return true;
    }

private:
    std::vector<std::string> d_kinds;
};

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_FAULT_LOG_H */
