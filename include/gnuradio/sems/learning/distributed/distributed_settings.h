// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: where a training process sits in a distributed run (torch-free).
 *
 * sems_train runs as one rank of N over LibTorch's c10d with the Gloo backend
 * (docs/reference/distributed_training.md). The rendezvous is a c10d FileStore (one machine, a
 * file every rank can reach) or a TCPStore served by rank 0 at master_addr:master_port.
 */
#ifndef INCLUDED_SEMS_LEARNING_DISTRIBUTED_SETTINGS_H
#define INCLUDED_SEMS_LEARNING_DISTRIBUTED_SETTINGS_H

#include <gnuradio/sems/learning/api.h>
#include <cstdint>
#include <string>

namespace gr {
namespace sems {

/*!
 * \brief Rank, world size and rendezvous of one training process.
 *
 * \details The default (world_size 1) trains alone, exactly as a plain single-process
 * run: no process group is created and no collective is called.
 */
struct SEMS_LEARNING_API distributed_settings {
    int rank = 0;             //!< this process, in [0, world_size)
    int world_size = 1;       //!< number of processes; 1 = train alone
    std::string master_addr;  //!< TCPStore host (rank 0's address), used when store_file is empty
    int master_port = 29500;  //!< TCPStore port (rank 0 listens on it)
    std::string store_file;   //!< FileStore path (one machine or a shared file system); wins over master_addr
    std::string interface;    //!< network interface for Gloo's connections (empty: see docs)
    bool agent_store = false; //!< the TCPStore is served by a launcher (torchrun's agent), not by rank 0
    double timeout_s = 300.0; //!< rendezvous and per-collective timeout: a dead or silent rank ends the run

    /*! \brief True when this process is one rank of several. \return world_size > 1. */
    bool enabled() const { return world_size > 1; }

    /*!
     * \brief The settings PyTorch's launchers export: WORLD_SIZE, RANK, MASTER_ADDR,
     * MASTER_PORT (and GLOO_SOCKET_IFNAME for the interface; TORCHELASTIC_USE_AGENT_STORE=True
     * when torchrun's agent serves the TCPStore).
     * \details Unset WORLD_SIZE gives world_size 1.
     * \return the settings.
     * \throws std::invalid_argument naming the variable when one is malformed or RANK is
     * missing while WORLD_SIZE > 1.
     */
    static distributed_settings from_environment();

    /*! \brief Throws std::invalid_argument naming the setting that is out of range. */
    void validate() const;

    /*! \brief True when the learning library was built with Gloo (libgloo-dev found). \return whether distributed runs are possible. */
    static bool available();
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_DISTRIBUTED_SETTINGS_H */
