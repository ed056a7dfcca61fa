// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: files the CppUnit suites make and edit (test-only, not installed). */
#ifndef INCLUDED_SEMS_LIB_QA_QA_FILES_H
#define INCLUDED_SEMS_LIB_QA_QA_FILES_H

#include <nlohmann/json.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

namespace gr {
namespace sems {
namespace qa {

// The shipped models/ folder of the source tree ($SEMS_SOURCE_DIR, set by CTest), with a
// trailing slash.
inline std::string models_dir()
{
    const char* src = std::getenv("SEMS_SOURCE_DIR");
    return std::string(src ? src : ".") + "/models/";
}

// A fresh directory path of this process under the temporary folder (removed if it exists).
inline std::string temp_dir(const std::string& suite, const std::string& name)
{
    auto d = std::filesystem::temp_directory_path() /
             ("sems_qa_" + suite + "_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(d);
    return d.string();
}

// Rewrites a JSON file through `f` (to plant a fault in a copy of a bundle).
inline void edit_json(const std::string& path, const std::function<void(nlohmann::json&)>& f)
{
    nlohmann::json j;
    std::ifstream(path) >> j;
    f(j);
    std::ofstream(path) << j.dump(2);
}

} // namespace qa
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_QA_QA_FILES_H */
