// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: data files found by name (class libraries, frames): an existing path, else
 * `<name>.json` in the folders of an environment variable, the source tree's
 * (SEMS_SOURCE_DIR/models/<kind>, and the one the library was built from), and the
 * installed share/gr-sems/models/<kind>. Internal to the library. */
#ifndef INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H
#define INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H

#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

inline bool file_exists(const std::string& p)
{
    std::ifstream f(p);
    return f.good();
}

// The file `name_or_path` names, or "" with `searched` listing every place looked at.
// `kind` is the folder under models/ (classes, frames); `built_in` the compiled-in folders.
inline std::string find_named_file(const std::string& name_or_path,
                                   const char* env_var,
                                   const std::string& kind,
                                   std::initializer_list<const char*> built_in,
                                   std::string& searched)
{
    if (file_exists(name_or_path))
        return name_or_path;
    std::vector<std::string> dirs;
    if (const char* env = std::getenv(env_var)) {
        std::stringstream ss(env);
        std::string d;
        while (std::getline(ss, d, ':'))
            if (!d.empty())
                dirs.push_back(d);
    }
    if (const char* src = std::getenv("SEMS_SOURCE_DIR"))
        dirs.push_back(std::string(src) + "/models/" + kind);
    for (const char* d : built_in)
        if (*d)
            dirs.push_back(d);
    searched = name_or_path;
    for (const auto& d : dirs) {
        const std::string p = d + "/" + name_or_path + ".json";
        if (file_exists(p))
            return p;
        searched += ", " + p;
    }
    return {};
}

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H */
