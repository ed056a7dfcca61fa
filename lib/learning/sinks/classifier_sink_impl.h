// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: classifier_sink implementation — a thin adapter: sink_core does the
 * stream bookkeeping, classifier_task the decoding and the scoring. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H
#define INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H

#include "learning/sinks/sink_block.h"
#include "learning/sinks/sink_core.h"
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <map>
#include <string>

namespace gr {
namespace sems {

// Classification: argmax of the class probabilities; accuracy and confusion matrix.
class classifier_task : public detail::sink_task
{
public:
    explicit classifier_task(std::unique_ptr<bundle_decoder> decoder);

    std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch) override;
    bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) override;
    pmt::pmt_t add_metrics(pmt::pmt_t dict) const override;
    void reset_metrics() override;

    double accuracy() const;
    const std::vector<std::vector<uint64_t>>& confusion() const { return d_confusion; }
    const std::vector<std::string>& class_names() const { return d_names; }
    // Refuses a truth whose `class_library` differs from the bundle's: throws
    // std::runtime_error naming both libraries and the difference. Each library name is
    // looked up (class_library::find) and compared once. A truth without the key passes.
    void check_library(const pmt::pmt_t& truth);

private:
    int class_of_truth(const pmt::pmt_t& truth) const; // -1: not one of the bundle's, -2: no class in truth

    std::unique_ptr<bundle_decoder> d_decoder;
    std::vector<std::string> d_names;
    uint64_t d_scored = 0;
    uint64_t d_correct = 0;
    std::vector<std::vector<uint64_t>> d_confusion;
    const pmt::pmt_t d_library_key;
    pmt::pmt_t d_accepted_library;               // the last library name that matched (a symbol)
    std::map<std::string, std::string> d_refusals; // library name -> why it is refused
};

class classifier_sink_impl : public detail::sink_block<classifier_sink, classifier_task>
{
public:
    classifier_sink_impl(const std::string& bundle_dir,
                         int n_pilots,
                         int batch_size,
                         int threads,
                         int metrics_period,
                         int n_symbols,
                         int n_subcarriers,
                         const std::string& frame);

    double accuracy() const override;
    std::vector<std::vector<uint64_t>> confusion() const override;
    std::vector<std::string> class_names() const override { return d_task.class_names(); }

    // Checks the class library of every truth tag before the frames go to the core: a
    // library other than the bundle's is a wrong flowgraph, not a bad frame. The refusal
    // is logged and ends the stream (WORK_DONE; an exception escaping work() would stop
    // this block's thread and hang the flowgraph).
    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    std::vector<gr::tag_t> d_truth_tags;
    bool d_refused = false;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H */
