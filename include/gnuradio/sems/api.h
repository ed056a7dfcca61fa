// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Symbol visibility of libgnuradio-sems (core + streaming blocks, no LibTorch).
 */
#ifndef INCLUDED_SEMS_API_H
#define INCLUDED_SEMS_API_H

#include <gnuradio/attributes.h>

#ifdef gnuradio_sems_EXPORTS
#define SEMS_API __GR_ATTR_EXPORT
#else
#define SEMS_API __GR_ATTR_IMPORT
#endif

#endif /* INCLUDED_SEMS_API_H */
