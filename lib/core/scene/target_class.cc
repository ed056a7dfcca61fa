// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the class table (docs/design.md §1; micro-Doppler displacements in target_class.h). */
#include <gnuradio/sems/core/scene/target_class.h>
#include <stdexcept>

namespace gr {
namespace sems {

const std::vector<class_spec>& class_table()
{
    static const std::vector<class_spec> table = {
        //  id                       name          range (m)   speed (m/s)  f_md (Hz)    A (m)
        { target_class::pedestrian, "pedestrian", 0.0, 200.0, 0.0, 2.0, 1.0, 3.0, 0.10 },
        { target_class::car, "car", 0.0, 200.0, 10.0, 20.0, 0.0, 0.0, 0.0 },
        { target_class::drone, "drone", 0.0, 200.0, 5.0, 10.0, 80.0, 120.0, 0.01 },
    };
    return table;
}

const class_spec& class_info(int class_id)
{
    const auto& t = class_table();
    if (class_id < 0 || class_id >= static_cast<int>(t.size()))
        throw std::invalid_argument("unknown target class id " + std::to_string(class_id));
    return t[class_id];
}

const class_spec& class_info(target_class c) { return class_info(static_cast<int>(c)); }

std::vector<std::string> class_names()
{
    std::vector<std::string> names;
    for (const auto& c : class_table())
        names.push_back(c.name);
    return names;
}

target_class class_from_name(const std::string& name)
{
    for (const auto& c : class_table())
        if (c.name == name)
            return c.id;
    std::string known;
    for (const auto& n : class_names())
        known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown target class \"" + name + "\" (known: " + known + ")");
}

} // namespace sems
} // namespace gr
