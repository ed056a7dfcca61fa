// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief An array as a block parameter names it: a preset, a file, or the file's JSON text.
 */
#ifndef INCLUDED_SEMS_CORE_ARRAY_SETTING_H
#define INCLUDED_SEMS_CORE_ARRAY_SETTING_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <string>

namespace gr {
namespace sems {

/*!
 * \brief Reads an array parameter: JSON text when its first non-blank character is '{' (a
 *        whole array file's text, `format` and `version` included), else a preset's name or an
 *        array file (array_geometry::find()).
 * \param setting the parameter's value.
 * \param who the block or app, named in errors.
 * \return the array.
 * \throws std::invalid_argument naming `who` when the setting is empty or its JSON does not
 *         parse, or naming the file and the field (array_geometry).
 */
SEMS_API array_geometry array_from_setting(const std::string& setting, const std::string& who);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_ARRAY_SETTING_H */
