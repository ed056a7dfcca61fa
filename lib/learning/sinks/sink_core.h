// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the classifier and delay-estimator sinks share (docs/design.md §3).
 *
 * sink_core turns a stream of pilot-observation frames (gr_complex[N_p] per item)
 * into batches for a bundle_decoder and the decoded batches back into one result
 * message per frame, in stream order:
 *   - frame index from the `sems_frame` tag on the item, else one past the last index;
 *   - truth from the `sems_truth` tag on the item, carried into the result;
 *   - a frame with a non-finite value is counted as skipped and never decoded;
 *   - a fault (an exception from the decoder, the scoring or the bookkeeping) never
 *     escapes: the frames it touches are counted as skipped and as faulted, the
 *     fault is reported once per kind (the block logs it), and the stream goes on;
 *   - frames are grouped into consecutive batches of exactly `batch_size` valid frames,
 *     whatever the sizes of the work() calls, so the decoder sees the same batches (and
 *     gives bit-identical answers) on every run; finish() decodes the partial last batch;
 *   - the running counters and a metrics message every `metrics_period` frames, and
 *     one at the end of the stream unless the last periodic one already holds its numbers.
 * What differs between the sinks (decoding, the answer keys, scoring, task metrics)
 * is a sink_task.
 *
 * Threads: push()/finish() run in the block's thread; the getters may be called from
 * any thread (Python) and take the same lock as the bookkeeping.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_SINK_CORE_H
#define INCLUDED_SEMS_LIB_LEARNING_SINK_CORE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/tags.h>
#include <pmt/pmt.h>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

// Loads the bundle in `dir` and refuses it (std::invalid_argument naming `block`, the
// bundle directory and the problem) unless it is a bundle for `task` on this stream:
// N_p pilots on an N x M frame, the frame named by `frame` (a preset or frame file; empty:
// the paper's frame with N x M), compared field by field. Returns the decoder, ready to run.
std::unique_ptr<bundle_decoder> load_decoder(const std::string& block,
                                             const std::string& dir,
                                             task_kind task,
                                             int n_pilots,
                                             int n_symbols,
                                             int n_subcarriers,
                                             const std::string& frame,
                                             int threads);

// Checks the integer parameters shared by both sinks (std::invalid_argument naming
// `block` and the parameter) and returns the input signature, gr_complex[n_pilots].
gr::io_signature::sptr
sink_input_signature(const std::string& block, int n_pilots, int batch_size, int threads, int metrics_period);

// N_r·N_p, the item's length of a sink whose items hold an array's pilots, with N_r checked
// first (std::invalid_argument naming `block` and n_elements, its own message, not N_p's).
int array_item_length(const std::string& block, int n_elements, int n_pilots);

// What the core knows of a frame besides its observations: its index and its truth.
struct frame_meta {
    uint64_t index;
    pmt::pmt_t truth; // PMT_NIL without a truth tag
    std::chrono::steady_clock::time_point arrived; // when work() handed it over (not when its batch is decoded)
};

// The task-specific half of a sink. Called with the core's lock held, except decode().
class sink_task
{
public:
    virtual ~sink_task() = default;
    // obs: batch x N_p, row-major, all finite; meta: the same frames' indices and truths, in
    // stream order (a frame skipped between two of them is not there: its index is). Returns
    // one dict per frame holding the answer.
    virtual std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch, const std::vector<frame_meta>& meta) = 0;
    // Scores the answer in `result` against `truth` (a dict); adds the score keys to
    // `result` and folds them into the running metrics. Returns false, changing nothing,
    // when the truth lacks what this task needs.
    virtual bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) = 0;
    // Adds the task's running metrics to `dict` and returns it.
    virtual pmt::pmt_t add_metrics(pmt::pmt_t dict) const = 0;
    virtual void reset_metrics() = 0;
    // The streams of a frame's observations: an item is elements() x N_p values (an array's
    // receive elements, element-major; 1 for one antenna).
    virtual int elements() const { return 1; }
};

class sink_core
{
public:
    // Where messages go: (port name, message). The block passes message_port_pub.
    using publish_fn = std::function<void(const pmt::pmt_t& port, const pmt::pmt_t& msg)>;

    sink_core(int n_pilots, int batch_size, int metrics_period, sink_task& task, publish_fn publish);

    // `count` frames (count x N_p, row-major); the first is absolute item `first_item`
    // and `tags` are the stream tags on them (others are ignored).
    void push(const gr_complex* frames, int count, uint64_t first_item, const std::vector<gr::tag_t>& tags);
    // Decodes the partial batch, if any, and publishes the final metrics (unless the
    // last periodic message already holds them).
    void finish();

    void set_metrics_period(int k); // 0: metrics only at the end of the stream
    int metrics_period() const;
    int batch_size() const { return d_batch; }
    int n_pilots() const { return d_np; }

    uint64_t frames() const;         // handled: answered or skipped
    uint64_t frames_scored() const;  // answered and compared with a truth
    uint64_t frames_skipped() const; // non-finite or faulted, never answered
    uint64_t frames_faulted() const; // skipped because decoding or bookkeeping failed

    // Where the first fault of each kind is reported: (kind, message). The block logs it.
    using fault_fn = std::function<void(const std::string& kind, const std::string& what)>;
    void set_fault_reporter(fault_fn f) { d_report = std::move(f); }
    // Test hook: called with the batch size before every decode (block thread); may throw
    // to inject a fault as a failing decoder would.
    void set_fault_injection(std::function<void(int batch)> f) { d_inject = std::move(f); }
    // Accounts for every frame handed to push() but not yet answered or skipped, as
    // faulted, after an exception escaped push(); the bookkeeping starts clean again.
    void recover(const std::string& kind, const std::string& what);
    // The metrics message: the counters plus the task's metrics.
    pmt::pmt_t metrics() const;
    void reset_metrics();

    // Runs `f` under the bookkeeping lock (for the task's own getters).
    template <class F>
    auto locked(F f) const
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        return f();
    }

private:
    struct pending_frame {
        uint64_t index;
        pmt::pmt_t truth; // PMT_NIL without a truth tag
        bool skipped;     // non-finite: no slot in d_obs
        std::chrono::steady_clock::time_point arrived;
    };

    void decode_pending();          // decodes the valid pending frames, then emits them
    void emit_ready_skips();        // skipped frames at the front of the queue go out now
    void emit_skip(bool faulted = false);
    void fault(const std::string& kind, const std::exception& e);
    void emit_result(const pending_frame& f, pmt::pmt_t result);
    void count_frame();             // one frame handled; metrics message every K
    pmt::pmt_t metrics_locked() const;
    pmt::pmt_t publish_metrics_locked(); // metrics_locked(), remembering what went out

    const int d_np;
    const int d_batch;
    sink_task& d_task;
    publish_fn d_publish;

    // Block thread only.
    std::deque<pending_frame> d_pending;
    std::vector<gr_complex> d_obs; // the valid pending frames, batch x N_p
    std::vector<frame_meta> d_meta; // their indices and truths
    int d_n_obs = 0;
    uint64_t d_next_index = 0;
    uint64_t d_entered = 0;          // frames handed to push(), ever (block thread only)
    uint64_t d_left = 0;             // frames answered or skipped, ever (block thread only)
    fault_fn d_report;
    std::function<void(int)> d_inject;
    std::vector<std::string> d_fault_kinds; // reported already

    // Shared with the getters.
    mutable std::mutex d_mutex;
    int d_metrics_period;
    uint64_t d_frames = 0;
    uint64_t d_scored = 0;
    uint64_t d_skipped = 0;
    uint64_t d_faulted = 0;
    bool d_published = false;        // a metrics message went out since the last reset
    uint64_t d_published_frames = 0; // d_frames in that message
};

// A number (real or integer) from a dict entry into `out`; false when absent or not a number.
bool dict_number(const pmt::pmt_t& dict, const char* key, double& out);
// A non-empty PMT dict (PMT_NIL, the empty dict, marks a frame without truth).
bool is_truth(const pmt::pmt_t& v);
// The truth's delay index into `index`: its delay_index, else its delay_s·B on `fs`; false when
// it has neither or the value is not finite (the delay and position sinks score against it).
bool truth_delay_index(const pmt::pmt_t& truth, const frame_settings& fs, double& index);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_SINK_CORE_H */
