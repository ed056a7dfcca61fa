// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Symbol visibility for libgnuradio-sems-learning.
 */
#ifndef INCLUDED_SEMS_LEARNING_API_H
#define INCLUDED_SEMS_LEARNING_API_H

#include <gnuradio/attributes.h>

#ifdef gnuradio_sems_learning_EXPORTS
#define SEMS_LEARNING_API __GR_ATTR_EXPORT
#else
#define SEMS_LEARNING_API __GR_ATTR_IMPORT
#endif

#endif /* INCLUDED_SEMS_LEARNING_API_H */
