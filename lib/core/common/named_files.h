// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: data files found by name (class libraries, frames): an existing path, else
 * `<name>.json` in the folders of an environment variable, the user's own folder
 * ($XDG_DATA_HOME or ~/.local/share, /gr-sems/models/<kind>), the source tree's
 * (SEMS_SOURCE_DIR/models/<kind>, and the one the library was built from), the
 * share/gr-sems/models/<kind> next to the installed library (wherever the module was
 * installed to), and the configured prefix's. Internal to the library. */
#ifndef INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H
#define INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H

#include <initializer_list>
#include <string>

namespace gr {
namespace sems {
namespace detail {

// Whether a name is a path rather than a name to look up: it has a '/' or ends in ".json".
bool names_a_path(const std::string& name);

// The canonical form of a path (symbolic links resolved), or the path itself if it does not exist.
std::string real_path(const std::string& path);

// The folder of the gr-sems shared library this code runs in (empty if unknown): the build
// tree's lib/ or the installed library folder, where the data folders are found relative to it.
std::string library_folder();

/*
 * The file `name_or_path` names, or "" with `searched` listing every place looked at.
 * A name with a '/' or ending in ".json" is a path and is only looked up as given.
 * `kind` is the folder under models/ (classes, frames); `built_in` the compiled-in folders
 * (the source tree's first, the configured install prefix's last).
 */
std::string find_named_file(const std::string& name_or_path,
                            const char* env_var,
                            const std::string& kind,
                            std::initializer_list<const char*> built_in,
                            std::string& searched);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_NAMED_FILES_H */
