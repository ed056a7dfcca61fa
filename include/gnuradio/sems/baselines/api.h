// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Symbol visibility for libgnuradio-sems-baselines.
 */
#ifndef INCLUDED_SEMS_BASELINES_API_H
#define INCLUDED_SEMS_BASELINES_API_H

#include <gnuradio/attributes.h>

#ifdef gnuradio_sems_baselines_EXPORTS
#define SEMS_BASELINES_API __GR_ATTR_EXPORT
#else
#define SEMS_BASELINES_API __GR_ATTR_IMPORT
#endif

#endif /* INCLUDED_SEMS_BASELINES_API_H */
