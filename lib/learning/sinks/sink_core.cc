// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: shared bookkeeping of the classifier and delay-estimator sinks. */
#include "learning/sinks/sink_core.h"
#include "blocks/common/stream_values.h"
#include "core/common/checks.h"

#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/common/tags.h>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <typeinfo>
#include <stdexcept>

namespace gr {
namespace sems {
namespace detail {

std::unique_ptr<bundle_decoder> load_decoder(const std::string& block,
                                             const std::string& dir,
                                             task_kind task,
                                             int n_pilots,
                                             int n_symbols,
                                             int n_subcarriers,
                                             const std::string& frame,
                                             int threads)
{
    if (dir.empty())
        throw std::invalid_argument(block + ": bundle: no model bundle directory given");
    frame_settings fs;
    try {
        if (!frame.empty()) {
            fs = frame_file::find(frame).frame;
        }
        frame_settings given = fs;
        given.n_symbols = n_symbols;
        given.n_subcarriers = n_subcarriers;
        if (frame.empty())
            fs = given;
        else // the block's N and M against its frame's
            fs.require_same(given, block, "frame '" + frame + "'", "the block's n_symbols/n_subcarriers");
        fs.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(block + ": frame settings: " + e.what());
    }
    model_bundle bundle;
    try {
        bundle = model_bundle::load(dir);
    } catch (const std::invalid_argument& e) {
        // load() names the file; say which block was being built.
        throw std::invalid_argument(block + ": cannot load model bundle: " + e.what());
    }
    bundle.check_compatible(fs, n_pilots, task, block); // names the bundle directory
    try {
        return std::make_unique<bundle_decoder>(bundle, threads);
    } catch (const std::exception& e) {
        throw std::invalid_argument(block + ": model bundle " + dir + ": cannot build the decoder: " + e.what());
    }
}

gr::io_signature::sptr
sink_input_signature(const std::string& block, int n_pilots, int batch_size, int threads, int metrics_period)
{
    auto bad = [&](const std::string& what, int v, const std::string& rule) {
        std::ostringstream s;
        s << block << ": " << what << " = " << v << ": " << rule;
        throw std::invalid_argument(s.str());
    };
    if (n_pilots < 1)
        bad("n_pilots", n_pilots, "must be at least 1");
    if (batch_size < 1)
        bad("batch_size", batch_size, "must be at least 1 (frames per inference call)");
    if (threads < 0)
        bad("threads", threads, "must be >= 0 (0 leaves LibTorch's thread count alone)");
    if (metrics_period < 0)
        bad("metrics_period", metrics_period, "must be >= 0 (0: metrics only at the end of the stream)");
    return gr::io_signature::make(1, 1, sizeof(gr_complex) * n_pilots);
}

int array_item_length(const std::string& block, int n_elements, int n_pilots)
{
    if (n_elements < 1 || n_elements > limits::max_array_elements)
        throw std::invalid_argument(block + ": n_elements must be in [1, " + std::to_string(limits::max_array_elements) +
                                    "], got " + std::to_string(n_elements));
    if (n_pilots < 1)
        throw std::invalid_argument(block + ": n_pilots must be >= 1, got " + std::to_string(n_pilots));
    return n_elements * n_pilots;
}

bool dict_number(const pmt::pmt_t& dict, const char* key, double& out)
{
    if (!pmt::is_dict(dict))
        return false;
    const pmt::pmt_t v = pmt::dict_ref(dict, pmt::intern(key), pmt::PMT_NIL);
    if (pmt::is_real(v) || pmt::is_integer(v) || pmt::is_uint64(v)) {
        out = pmt::to_double(v);
        return true;
    }
    return false;
}

bool truth_delay_index(const pmt::pmt_t& truth, const frame_settings& fs, double& index)
{
    if (!dict_number(truth, keys::delay_index, index)) {
        double delay_s;
        if (!dict_number(truth, keys::delay_s, delay_s))
            return false;
        index = fs.delay_index(delay_s);
    }
    return checks::finite(index);
}

bool is_truth(const pmt::pmt_t& v)
{
    // PMT's is_dict() is true for nil (the empty dict): a frame without a truth tag.
    return pmt::is_dict(v) && !pmt::is_null(v);
}

sink_core::sink_core(int n_pilots, int batch_size, int metrics_period, sink_task& task, publish_fn publish)
    : d_np(n_pilots),
      d_batch(batch_size),
      d_task(task),
      d_publish(std::move(publish)),
      d_obs(static_cast<size_t>(batch_size) * n_pilots),
      d_metrics_period(metrics_period)
{
}

void sink_core::push(const gr_complex* frames,
                     int count,
                     uint64_t first_item,
                     const std::vector<gr::tag_t>& tags)
{
    static const pmt::pmt_t frame_key = pmt::intern(keys::frame_tag);
    static const pmt::pmt_t truth_key = pmt::intern(keys::truth_tag);

    d_entered += static_cast<uint64_t>(count); // recover() accounts for them if anything below throws

    // Tags per item of this call (the extractor puts both on the frame's item).
    std::vector<pmt::pmt_t> truth(count, pmt::PMT_NIL);
    std::vector<int64_t> index(count, -1);
    for (const auto& t : tags) {
        if (t.offset < first_item || t.offset >= first_item + static_cast<uint64_t>(count))
            continue;
        const size_t i = t.offset - first_item;
        const auto idx = pmt::eq(t.key, frame_key) ? frame_index_of(t.value) : std::optional<uint64_t>{};
        if (idx)
            index[i] = static_cast<int64_t>(*idx);
        else if (pmt::eq(t.key, truth_key) && is_truth(t.value))
            truth[i] = t.value;
    }

    const auto now = std::chrono::steady_clock::now(); // once per call: the frames' arrival
    for (int i = 0; i < count; i++) {
        const gr_complex* frame = frames + static_cast<size_t>(i) * d_np;
        pending_frame f;
        f.arrived = now;
        f.index = index[i] >= 0 ? static_cast<uint64_t>(index[i]) : d_next_index;
        d_next_index = f.index + 1;
        f.truth = truth[i];
        f.skipped = !all_finite(frame, d_np);
        if (!f.skipped) {
            std::copy(frame, frame + d_np, d_obs.begin() + static_cast<size_t>(d_n_obs) * d_np);
            d_n_obs++;
        }
        d_pending.push_back(std::move(f));
        if (d_n_obs == d_batch)
            decode_pending();
        else
            emit_ready_skips();
    }
}

void sink_core::finish()
{
    if (d_n_obs > 0)
        decode_pending();
    emit_ready_skips();
    // The final numbers, unless the last periodic message already carried them.
    pmt::pmt_t msg = pmt::PMT_NIL;
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        if (!d_published || d_frames != d_published_frames)
            msg = publish_metrics_locked();
    }
    if (msg != pmt::PMT_NIL)
        d_publish(pmt::intern(keys::metrics_port), msg);
}

void sink_core::decode_pending()
{
    // Decode without the lock: getters stay responsive during inference.
    std::vector<pmt::pmt_t> answers;
    bool ok = true;
    try {
        if (d_inject)
            d_inject(d_n_obs);
        d_meta.clear();
        for (const auto& f : d_pending)
            if (!f.skipped)
                d_meta.push_back({ f.index, f.truth, f.arrived });
        answers = d_task.decode(d_obs.data(), d_n_obs, d_meta);
        if (static_cast<int>(answers.size()) != d_n_obs)
            throw std::logic_error("sink_core: the decoder returned " + std::to_string(answers.size()) +
                                   " answers for " + std::to_string(d_n_obs) + " frames");
    } catch (const std::exception& e) {
        fault("decode", e);
        ok = false;
    }
    d_n_obs = 0;
    size_t next = 0;
    while (!d_pending.empty()) {
        pending_frame f = std::move(d_pending.front());
        d_pending.pop_front();
        if (f.skipped) {
            emit_skip();
        } else if (!ok) {
            emit_skip(true);
        } else {
            try {
                emit_result(f, answers[next++]);
            } catch (const std::exception& e) {
                fault("score", e);
                emit_skip(true);
            }
        }
    }
}

void sink_core::fault(const std::string& where, const std::exception& e)
{
    const std::string kind = where + " (" + typeid(e).name() + ")";
    if (std::find(d_fault_kinds.begin(), d_fault_kinds.end(), kind) != d_fault_kinds.end())
        return; // reported once per kind; the counters carry the rest
    d_fault_kinds.push_back(kind);
    if (d_report)
        d_report(kind, e.what());
}

void sink_core::recover(const std::string& kind, const std::string& what)
{
    if (std::find(d_fault_kinds.begin(), d_fault_kinds.end(), kind) == d_fault_kinds.end()) {
        d_fault_kinds.push_back(kind);
        if (d_report)
            d_report(kind, what);
    }
    d_pending.clear();
    d_n_obs = 0;
    while (d_left < d_entered)
        emit_skip(true);
}

void sink_core::emit_ready_skips()
{
    while (!d_pending.empty() && d_pending.front().skipped) {
        emit_skip();
        d_pending.pop_front();
    }
}

void sink_core::emit_skip(bool faulted)
{
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        d_skipped++;
        d_faulted += faulted ? 1 : 0;
    }
    count_frame();
}

void sink_core::emit_result(const pending_frame& f, pmt::pmt_t result)
{
    result = pmt::dict_add(result, pmt::intern(keys::frame), pmt::from_uint64(f.index));
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        if (is_truth(f.truth)) {
            result = pmt::dict_add(result, pmt::intern(keys::truth), f.truth);
            if (d_task.score(result, f.truth))
                d_scored++;
        }
    }
    d_publish(pmt::intern(keys::result_port), result);
    count_frame();
}

void sink_core::count_frame()
{
    d_left++;
    pmt::pmt_t msg = pmt::PMT_NIL;
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        d_frames++;
        if (d_metrics_period > 0 && d_frames % static_cast<uint64_t>(d_metrics_period) == 0)
            msg = publish_metrics_locked();
    }
    if (msg != pmt::PMT_NIL)
        d_publish(pmt::intern(keys::metrics_port), msg);
}

void sink_core::set_metrics_period(int k)
{
    if (k < 0)
        throw std::invalid_argument("metrics_period must be >= 0 (0: metrics only at the end of the stream)");
    std::lock_guard<std::mutex> lock(d_mutex);
    d_metrics_period = k;
}

int sink_core::metrics_period() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_metrics_period;
}

uint64_t sink_core::frames() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_frames;
}

uint64_t sink_core::frames_scored() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_scored;
}

uint64_t sink_core::frames_skipped() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_skipped;
}

uint64_t sink_core::frames_faulted() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_faulted;
}

pmt::pmt_t sink_core::metrics() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return metrics_locked();
}

pmt::pmt_t sink_core::metrics_locked() const
{
    pmt::pmt_t d = pmt::make_dict();
    d = pmt::dict_add(d, pmt::intern(keys::frames), pmt::from_uint64(d_frames));
    d = pmt::dict_add(d, pmt::intern(keys::frames_scored), pmt::from_uint64(d_scored));
    d = pmt::dict_add(d, pmt::intern(keys::frames_skipped), pmt::from_uint64(d_skipped));
    d = pmt::dict_add(d, pmt::intern(keys::frames_faulted), pmt::from_uint64(d_faulted));
    return d_task.add_metrics(d);
}

pmt::pmt_t sink_core::publish_metrics_locked()
{
    d_published = true;
    d_published_frames = d_frames;
    return metrics_locked();
}

void sink_core::reset_metrics()
{
    std::lock_guard<std::mutex> lock(d_mutex);
    d_frames = d_scored = d_skipped = d_faulted = 0;
    d_published = false;
    d_task.reset_metrics();
}

} // namespace detail
} // namespace sems
} // namespace gr
