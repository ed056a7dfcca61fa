// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the block half both sinks share (internal).
 *
 * A sink is a sync block with one gr_complex[N_p] input (N_r·N_p for an array's: the task's
 * elements()) and no output whose work()
 * hands every item and tag to detail::sink_core; the task (classifier_task,
 * delay_task) decodes and scores. This template holds that adapter once; the sink
 * impls add only their task-specific getters.
 *
 * gr::sync_block is a virtual base of the public block classes, so the most-derived
 * impl constructs it (name and signatures); this base builds the task and the core.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_SINK_BLOCK_H
#define INCLUDED_SEMS_LIB_LEARNING_SINK_BLOCK_H

#include "learning/sinks/sink_core.h"
#include <gnuradio/sems/core/common/tags.h>
#include <string>
#include <typeinfo>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

template <typename Base, typename Task>
class sink_block : public Base
{
public:
    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star&) override
    {
        // Nothing escapes work(): GNU Radio would end this block's thread and the flowgraph
        // would hang. sink_core isolates decoder and scoring faults itself; anything else
        // (the tag reader, the bookkeeping) is caught here and the frames it touched are
        // counted as faulted. Either way the fault is logged once per kind.
        try {
            const uint64_t first = this->nitems_read(0);
            this->get_tags_in_range(d_tags, 0, first, first + noutput_items);
            d_core.push(static_cast<const gr_complex*>(input_items[0]), noutput_items, first, d_tags);
        } catch (const std::exception& e) {
            d_core.recover(std::string("work (") + typeid(e).name() + ")", e.what());
        }
        return noutput_items;
    }

    bool stop() override
    {
        // stop() runs in the executor's destructor, also while a work() exception unwinds:
        // throwing here would terminate the process.
        try {
            d_core.finish();
        } catch (const std::exception& e) {
            this->d_logger->error("end of stream: {}", e.what());
        }
        return true;
    }

    uint64_t frames() const override { return d_core.frames(); }
    uint64_t frames_scored() const override { return d_core.frames_scored(); }
    uint64_t frames_skipped() const override { return d_core.frames_skipped(); }
    uint64_t frames_faulted() const override { return d_core.frames_faulted(); }

    // Test hook (not in the public API): see sink_core::set_fault_injection.
    sink_core& core_for_test() { return d_core; }
    void reset_metrics() override { d_core.reset_metrics(); }
    int batch_size() const override { return d_core.batch_size(); }
    int metrics_period() const override { return d_core.metrics_period(); }
    void set_metrics_period(int k) override { d_core.set_metrics_period(k); }

protected:
    // task_args: what the task takes after its decoder.
    template <typename... TaskArgs>
    sink_block(const char* name,
               task_kind kind,
               const std::string& bundle_dir,
               int n_pilots,
               int batch_size,
               int threads,
               int metrics_period,
               int n_symbols,
               int n_subcarriers,
               const std::string& frame,
               TaskArgs&&... task_args)
        : d_task(load_decoder(name, bundle_dir, kind, n_pilots, n_symbols, n_subcarriers, frame, threads),
                 std::forward<TaskArgs>(task_args)...),
          d_core(n_pilots * d_task.elements(), batch_size, metrics_period, d_task,
                 [this](const pmt::pmt_t& port, const pmt::pmt_t& msg) {
              this->message_port_pub(port, msg);
          })
    {
        d_core.set_fault_reporter([this](const std::string& kind, const std::string& what) {
            this->d_logger->error("fault in {}: {}; the frames it touched are counted in frames_faulted "
                                  "and skipped (further faults of this kind are only counted)",
                                  kind, what);
        });
        this->message_port_register_out(pmt::intern(keys::result_port));
        this->message_port_register_out(pmt::intern(keys::metrics_port));
    }

    Task d_task;
    sink_core d_core;

private:
    std::vector<gr::tag_t> d_tags;
};

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_SINK_BLOCK_H */
