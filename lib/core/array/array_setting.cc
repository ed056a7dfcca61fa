// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: an array parameter read as JSON text, a preset's name or a file (array_setting.h). */
#include <gnuradio/sems/core/array/array_setting.h>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace gr {
namespace sems {

array_geometry array_from_setting(const std::string& setting, const std::string& who)
{
    const auto first = setting.find_first_not_of(" \t\r\n");
    if (first == std::string::npos)
        throw std::invalid_argument(who + ": array is empty: give a preset's name (e.g. ula8_3g), an array file "
                                          "(format sems.array) or its JSON text");
    if (setting[first] != '{')
        return array_geometry::find(setting);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(setting);
    } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument(who + ": array JSON text does not parse: " + e.what());
    }
    return array_geometry::from_json(j, who + " array JSON");
}

} // namespace sems
} // namespace gr
