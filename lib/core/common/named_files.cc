// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: data files found by name (named_files.h). */
#include "named_files.h"

#include <dlfcn.h>
#include <climits>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

// The installed data folder relative to the installed library folder (lib/core/CMakeLists.txt
// sets it for this file): an install moved or made to another prefix finds its own files.
#ifndef SEMS_LIBDIR_TO_MODELS
#define SEMS_LIBDIR_TO_MODELS ""
#endif

namespace gr {
namespace sems {
namespace detail {
namespace {

bool file_exists(const std::string& p)
{
    std::ifstream f(p);
    return f.good();
}

bool ends_with(const std::string& s, const std::string& tail)
{
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

} // namespace

bool names_a_path(const std::string& name) { return name.find('/') != std::string::npos || ends_with(name, ".json"); }

std::string real_path(const std::string& path)
{
    char buf[PATH_MAX];
    return ::realpath(path.c_str(), buf) ? std::string(buf) : path;
}

std::string library_folder()
{
    Dl_info info;
    if (::dladdr(reinterpret_cast<void*>(&library_folder), &info) == 0 || !info.dli_fname)
        return {};
    const std::string lib = real_path(info.dli_fname);
    const auto slash = lib.rfind('/');
    return slash == std::string::npos ? std::string() : lib.substr(0, slash);
}

std::string find_named_file(const std::string& name_or_path,
                            const char* env_var,
                            const std::string& kind,
                            std::initializer_list<const char*> built_in,
                            std::string& searched)
{
    if (file_exists(name_or_path))
        return name_or_path;
    searched = name_or_path;
    if (names_a_path(name_or_path))
        return {}; // a path, and it does not exist
    std::vector<std::string> dirs;
    auto add = [&dirs](const std::string& d) {
        for (const auto& have : dirs)
            if (have == d)
                return;
        dirs.push_back(d);
    };
    if (const char* env = std::getenv(env_var)) {
        std::stringstream ss(env);
        std::string d;
        while (std::getline(ss, d, ':'))
            if (!d.empty())
                add(d);
    }
    // The user's own folder needs no variable: GNU Radio Companion (started from a desktop
    // menu, without the shell's exports) finds a user's libraries and frames there.
    if (const char* data = std::getenv("XDG_DATA_HOME"); data && *data)
        add(std::string(data) + "/gr-sems/models/" + kind);
    else if (const char* home = std::getenv("HOME"); home && *home)
        add(std::string(home) + "/.local/share/gr-sems/models/" + kind);
    if (const char* src = std::getenv("SEMS_SOURCE_DIR"); src && *src)
        add(std::string(src) + "/models/" + kind);
    const std::vector<const char*> fixed(built_in);
    for (size_t i = 0; i + 1 < fixed.size(); ++i) // the source tree's (and any but the last)
        if (*fixed[i])
            add(fixed[i]);
    if (const std::string lib = library_folder(); !lib.empty() && *SEMS_LIBDIR_TO_MODELS)
        add(lib + "/" + SEMS_LIBDIR_TO_MODELS + "/" + kind); // next to the installed library
    if (!fixed.empty() && *fixed.back())
        add(fixed.back()); // the configured install prefix's
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
