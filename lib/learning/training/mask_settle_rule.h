// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: when the trainer's phase 1 may stop learning the mask
 * (training_settings::mask_settle_epochs). */
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The learned mask has settled once it has been the same set of grid positions for
 * `epochs` consecutive epochs after the first (0: it never settles, phase 1 runs every epoch).
 * \details Every rank of a distributed run holds the same encoder, so each sees the same
 * masks and stops at the same epoch.
 */
class mask_settle_rule
{
public:
    explicit mask_settle_rule(int epochs) : d_epochs(epochs) {}

    //! Records one epoch's mask (flat indices, any order). \return true once settled.
    bool settled_after(std::vector<int64_t> mask)
    {
        std::sort(mask.begin(), mask.end());
        d_unchanged = d_seen && mask == d_previous ? d_unchanged + 1 : 0;
        d_previous = std::move(mask);
        d_seen = true;
        return d_epochs > 0 && d_unchanged >= d_epochs;
    }
    //! Epochs the mask has stayed the same (0 after a change).
    int unchanged() const { return d_unchanged; }

private:
    int d_epochs;
    int d_unchanged = 0;
    bool d_seen = false;
    std::vector<int64_t> d_previous;
};

} // namespace sems
} // namespace gr
