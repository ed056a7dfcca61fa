// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the command a program records in what it writes (bundle.json, a mask's origin): as
 * typed, the program by its name, not where this machine keeps it. */
#ifndef INCLUDED_SEMS_APPS_COMMAND_LINE_H
#define INCLUDED_SEMS_APPS_COMMAND_LINE_H

#include <sstream>
#include <string>

namespace gr {
namespace sems {
namespace apps {

inline std::string command_of(int argc, char** argv)
{
    std::ostringstream cmd;
    const std::string program = argv[0];
    cmd << program.substr(program.rfind('/') == std::string::npos ? 0 : program.rfind('/') + 1);
    for (int i = 1; i < argc; ++i)
        cmd << " " << argv[i];
    return cmd.str();
}

} // namespace apps
} // namespace sems
} // namespace gr

#endif
