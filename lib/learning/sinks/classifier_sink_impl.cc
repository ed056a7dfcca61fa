// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: classifier_sink implementation. */
#include "learning/sinks/classifier_sink_impl.h"

#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/array/array_setting.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {
constexpr const char* block_name = "classifier_sink";
} // namespace

// ---------------------------------------------------------------- classifier_task

classifier_task::classifier_task(std::unique_ptr<bundle_decoder> decoder,
                                 double track_idle_s,
                                 int n_elements,
                                 const std::string& array)
    : d_azimuth_key(pmt::intern(keys::azimuth_rad)),
      d_label_key(pmt::intern(keys::label)),
      d_class_name_key(pmt::intern(keys::class_name)),
      d_probs_key(pmt::intern(keys::probs)),
      d_track_frames_key(pmt::intern(keys::track_frames)),
      d_track_id_key(pmt::intern(keys::track_id)),
      d_library_key(pmt::intern(keys::class_library)),
      d_accepted_library(pmt::PMT_NIL)
{
    d_idle_s = track_idle_s;
    if (!(std::isfinite(track_idle_s) && track_idle_s >= 0.0))
        throw std::invalid_argument(std::string(block_name) + ": track_idle_s must be a finite time >= 0 s (0: no idle "
                                    "limit), got " + std::to_string(track_idle_s));
    d_elements = n_elements;
    if (!array.empty() || n_elements != 1) {
        if (array.find_first_not_of(" \t\r\n") == std::string::npos)
            throw std::invalid_argument(std::string(block_name) + ": n_elements = " + std::to_string(n_elements) +
                                        " needs the array its streams come from (array: a preset's name, an array "
                                        "file or its JSON text)");
        const array_geometry a = array_from_setting(array, block_name);
        if (a.n_transmit() != 1)
            throw std::invalid_argument(std::string(block_name) + ": the array has " + std::to_string(a.n_transmit()) +
                                        " transmit elements; the classifier sink beamforms the streams of one");
        if (a.n_receive() != n_elements)
            throw std::invalid_argument(std::string(block_name) + ": the array has " + std::to_string(a.n_receive()) +
                                        " receive elements, but n_elements = " + std::to_string(n_elements));
        const auto& b = decoder->bundle();
        d_beamformer = std::make_unique<array_beamformer>(a, pilot_wavelength_m(b.frame, b.mask));
    }
    if (track_classifier::is_track_bundle(decoder->bundle()))
        d_track = std::make_unique<track_classifier>(std::move(decoder));
    else
        d_decoder = std::move(decoder);
    d_names = bundle().class_names;
    for (const auto& n : d_names)
        d_name_symbols.push_back(pmt::intern(n));
    reset_metrics();
}

// Each frame's set of the bundle's super-frame mask: its frame index mod F, the rule the
// pilot mapper and extractor pick their sets by (all 0 for one frame's mask).
std::vector<int> classifier_task::sets_of(const std::vector<detail::frame_meta>& meta, int batch) const
{
    if (static_cast<int>(meta.size()) != batch)
        throw std::logic_error("classifier_sink: " + std::to_string(meta.size()) + " frames described for a batch of " +
                               std::to_string(batch));
    const uint64_t f = static_cast<uint64_t>(bundle().super_frames());
    std::vector<int> sets(meta.size());
    for (size_t i = 0; i < meta.size(); ++i)
        sets[i] = static_cast<int>(meta[i].index % f);
    return sets;
}

pmt::pmt_t classifier_task::answer(const float* p) const
{
    const size_t c = d_names.size();
    const int label = static_cast<int>(std::max_element(p, p + c) - p);
    pmt::pmt_t d = pmt::make_dict();
    d = pmt::dict_add(d, d_label_key, pmt::from_long(label));
    d = pmt::dict_add(d, d_class_name_key, d_name_symbols[static_cast<size_t>(label)]);
    return pmt::dict_add(d, d_probs_key, pmt::init_f32vector(c, p));
}

const gr_complex* classifier_task::combine(const gr_complex* obs, int batch)
{
    if (!d_beamformer)
        return obs;
    const size_t np = static_cast<size_t>(bundle().mask.size()), per = np * static_cast<size_t>(d_elements);
    d_beamformed.resize(static_cast<size_t>(batch) * np);
    d_azimuths.resize(static_cast<size_t>(batch));
    for (int i = 0; i < batch; ++i)
        d_azimuths[size_t(i)] = d_beamformer->combine(obs + size_t(i) * per, static_cast<int>(np),
                                                       d_beamformed.data() + size_t(i) * np);
    return d_beamformed.data();
}

std::vector<pmt::pmt_t> classifier_task::with_azimuths(std::vector<pmt::pmt_t> answers) const
{
    if (d_beamformer)
        for (size_t i = 0; i < answers.size(); ++i)
            answers[i] = pmt::dict_add(answers[i], d_azimuth_key, pmt::from_double(d_azimuths[i]));
    return answers;
}

std::vector<pmt::pmt_t>
classifier_task::decode(const gr_complex* frames, int batch, const std::vector<detail::frame_meta>& meta)
{
    const gr_complex* obs = combine(frames, batch);
    if (d_track)
        return with_azimuths(decode_tracks(obs, batch, meta));
    const std::vector<int> sets = sets_of(meta, batch);
    const std::vector<float> probs = d_decoder->classify(obs, batch, sets.data());
    const size_t c = d_names.size();
    if (probs.size() != static_cast<size_t>(batch) * c) // never step past the probability vector
        throw std::logic_error("classifier_sink: the decoder returned " + std::to_string(probs.size()) +
                               " probabilities for " + std::to_string(batch) + " frames of " + std::to_string(c) +
                               " classes");
    std::vector<pmt::pmt_t> out;
    out.reserve(batch);
    for (int i = 0; i < batch; i++)
        out.push_back(answer(probs.data() + i * c));
    return with_azimuths(std::move(out));
}

// Track mode: the frame decoder over the batch, then one step per frame on the track it
// belongs to. A track starts again (its state from zero) at the first frame, at a new
// track_id, at a frame that does not follow the track's last one (a gap: frames lost,
// skipped or out of order), and after track_idle_s of wall time without a frame.
std::vector<pmt::pmt_t>
classifier_task::decode_tracks(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>& meta)
{
    if (static_cast<int>(meta.size()) != batch)
        throw std::logic_error("classifier_sink: " + std::to_string(meta.size()) + " frames described for a batch of " +
                               std::to_string(batch));
    const std::vector<int> sets = sets_of(meta, batch);
    const std::vector<float> ev = d_track->evidence(obs, batch, sets.data());
    const size_t e = static_cast<size_t>(d_track->evidence_size());
    if (ev.size() != static_cast<size_t>(batch) * e)
        throw std::logic_error("classifier_sink: the frame decoder returned " + std::to_string(ev.size()) +
                               " evidence values for " + std::to_string(batch) + " frames of " + std::to_string(e));
    d_probs.resize(d_names.size());
    std::vector<pmt::pmt_t> out;
    out.reserve(batch);
    for (int i = 0; i < batch; ++i) {
        const auto& m = meta[static_cast<size_t>(i)];
        const pmt::pmt_t id =
            detail::is_truth(m.truth) ? pmt::dict_ref(m.truth, d_track_id_key, pmt::PMT_NIL) : pmt::PMT_NIL;
        const bool known = pmt::is_integer(id) || pmt::is_uint64(id);
        const uint64_t track = known ? pmt::to_uint64(id) : 0;
        bool fresh = !d_in_track || known != d_track_known || (known && track != d_track_id);
        if (!fresh && m.index != d_last_index + 1) {
            fresh = true;
            ++d_track_gaps;
        }
        if (!fresh && d_idle_s > 0.0 && std::chrono::duration<double>(m.arrived - d_last_seen).count() > d_idle_s) {
            fresh = true;
            ++d_track_idle;
        }
        if (fresh) {
            d_state = d_track->begin();
            d_in_track = true;
            d_track_known = known;
            d_track_id = track;
            ++d_tracks_started;
        }
        d_last_index = m.index;
        d_last_seen = m.arrived;
        d_track->step(d_state, ev.data() + static_cast<size_t>(i) * e, d_probs.data());
        pmt::pmt_t d = answer(d_probs.data());
        d = pmt::dict_add(d, d_track_frames_key, pmt::from_uint64(d_state.frames));
        if (known)
            d = pmt::dict_add(d, d_track_id_key, pmt::from_uint64(track));
        out.push_back(d);
    }
    return out;
}

int classifier_task::class_of_truth(const pmt::pmt_t& truth) const
{
    // By name, so a bundle trained on a subset of classes (or in another order) scores right.
    std::string name;
    const pmt::pmt_t n = pmt::dict_ref(truth, pmt::intern(keys::class_name), pmt::PMT_NIL);
    if (pmt::is_symbol(n)) {
        name = pmt::symbol_to_string(n);
    } else {
        const pmt::pmt_t id = pmt::dict_ref(truth, pmt::intern(keys::class_id), pmt::PMT_NIL);
        if (!pmt::is_integer(id))
            return -2;
        try {
            // An id of the input's library, the bundle's (check_library refuses any other).
            const auto& lib = bundle().library;
            const int c = static_cast<int>(pmt::to_long(id));
            name = lib ? lib->at(c).name : class_info(c).name;
        } catch (const std::exception&) {
            return -1;
        }
    }
    const auto it = std::find(d_names.begin(), d_names.end(), name);
    return it == d_names.end() ? -1 : static_cast<int>(it - d_names.begin());
}

void classifier_task::check_library(const pmt::pmt_t& truth)
{
    const pmt::pmt_t lib = pmt::dict_ref(truth, d_library_key, pmt::PMT_NIL);
    if (!pmt::is_symbol(lib) || pmt::eq(lib, d_accepted_library)) // the common case: one pointer compare
        return;
    const std::string name = pmt::symbol_to_string(lib);
    auto known = d_refusals.find(name);
    if (known == d_refusals.end()) {
        std::string why;
        const auto& bundle = this->bundle();
        try {
            bundle.check_library(*class_library::find(name), block_name);
        } catch (const std::runtime_error& e) {
            why = e.what();
        } catch (const std::invalid_argument& e) { // a library this machine cannot find
            if (!bundle.library || bundle.library->name() != name)
                why = std::string(block_name) + ": the bundle " + bundle.directory + " was trained on class library \"" +
                      (bundle.library ? bundle.library->name() : std::string("paper")) +
                      "\" but its input's frames come from class library \"" + name + "\", which cannot be read: " +
                      e.what();
        }
        known = d_refusals.emplace(name, why).first;
    }
    if (!known->second.empty())
        throw std::runtime_error(known->second);
    d_accepted_library = lib;
}

bool classifier_task::score(pmt::pmt_t& result, const pmt::pmt_t& truth)
{
    const int t = class_of_truth(truth);
    if (t == -2)
        return false;
    const int label = static_cast<int>(pmt::to_long(pmt::dict_ref(result, pmt::intern(keys::label), pmt::PMT_NIL)));
    const bool correct = (t == label);
    result = pmt::dict_add(result, pmt::intern(keys::correct), pmt::from_bool(correct));
    d_scored++;
    d_correct += correct ? 1 : 0;
    if (t >= 0)
        d_confusion[t][label]++;
    return true;
}

double classifier_task::accuracy() const
{
    return d_scored ? static_cast<double>(d_correct) / d_scored : std::numeric_limits<double>::quiet_NaN();
}

pmt::pmt_t classifier_task::add_metrics(pmt::pmt_t dict) const
{
    dict = pmt::dict_add(dict, pmt::intern(keys::accuracy), pmt::from_double(accuracy()));
    if (d_track) {
        dict = pmt::dict_add(dict, pmt::intern(keys::tracks_started), pmt::from_uint64(d_tracks_started));
        dict = pmt::dict_add(dict, pmt::intern(keys::track_gaps), pmt::from_uint64(d_track_gaps));
        dict = pmt::dict_add(dict, pmt::intern(keys::track_idle_resets), pmt::from_uint64(d_track_idle));
    }
    // confusion: a vector of rows (truth), each a vector of uint64 counts over the predicted
    // classes; plain PMT vectors because pmt.to_python cannot convert a u64vector.
    pmt::pmt_t rows = pmt::make_vector(d_confusion.size(), pmt::PMT_NIL);
    for (size_t i = 0; i < d_confusion.size(); i++) {
        pmt::pmt_t row = pmt::make_vector(d_confusion[i].size(), pmt::PMT_NIL);
        for (size_t j = 0; j < d_confusion[i].size(); j++)
            pmt::vector_set(row, j, pmt::from_uint64(d_confusion[i][j]));
        pmt::vector_set(rows, i, row);
    }
    return pmt::dict_add(dict, pmt::intern(keys::confusion), rows);
}

void classifier_task::reset_metrics()
{
    d_scored = d_correct = 0;
    d_tracks_started = 0;
    d_track_gaps = 0;
    d_track_idle = 0;
    d_confusion.assign(d_names.size(), std::vector<uint64_t>(d_names.size(), 0));
}

// ---------------------------------------------------------------- classifier_sink

classifier_sink::sptr classifier_sink::make(const std::string& bundle_dir,
                                            int n_pilots,
                                            int batch_size,
                                            int threads,
                                            int metrics_period,
                                            int n_symbols,
                                            int n_subcarriers,
                                            const std::string& frame,
                                            double track_idle_s,
                                            int super_frames,
                                            int n_elements,
                                            const std::string& array)
{
    return gnuradio::make_block_sptr<classifier_sink_impl>(bundle_dir, n_pilots, batch_size, threads, metrics_period,
                                                           n_symbols, n_subcarriers, frame, track_idle_s, super_frames,
                                                           n_elements, array);
}

classifier_sink_impl::classifier_sink_impl(const std::string& bundle_dir,
                                           int n_pilots,
                                           int batch_size,
                                           int threads,
                                           int metrics_period,
                                           int n_symbols,
                                           int n_subcarriers,
                                           const std::string& frame,
                                           double track_idle_s,
                                           int super_frames,
                                           int n_elements,
                                           const std::string& array)
    : gr::sync_block(block_name,
                     detail::sink_input_signature(block_name, detail::array_item_length(block_name, n_elements, n_pilots), batch_size, threads,
                                                  metrics_period),
                     gr::io_signature::make(0, 0, 0)),
      sink_block(block_name, task_kind::classify, bundle_dir, n_pilots, batch_size, threads, metrics_period,
                 n_symbols, n_subcarriers, frame, track_idle_s, n_elements, array)
{
    // The stream's super-frame and the bundle's, like n_pilots against its N_p: the sets are
    // picked by frame index mod F, so another F would read frames at pilots they do not carry.
    const int f = d_task.super_frames();
    if (super_frames != f)
        throw std::invalid_argument(std::string(block_name) + ": the stream's pilot mask spans super_frames = " +
                                    std::to_string(super_frames) + " frame(s), but bundle " + bundle_dir +
                                    "'s mask spans " + std::to_string(f) + ": give the mapper and the extractor the "
                                    "bundle's own mask.json and super_frames = " + std::to_string(f));
}

uint64_t classifier_sink_impl::tracks_started() const
{
    return d_core.locked([this] { return d_task.tracks_started(); });
}

uint64_t classifier_sink_impl::track_gaps() const
{
    return d_core.locked([this] { return d_task.track_gaps(); });
}

int classifier_sink_impl::work(int noutput_items,
                               gr_vector_const_void_star& input_items,
                               gr_vector_void_star& output_items)
{
    if (d_refused)
        return WORK_DONE;
    static const pmt::pmt_t truth_key = pmt::intern(keys::truth_tag);
    const uint64_t first = nitems_read(0);
    get_tags_in_range(d_truth_tags, 0, first, first + static_cast<uint64_t>(noutput_items), truth_key);
    try {
        for (const auto& t : d_truth_tags)
            if (detail::is_truth(t.value))
                d_task.check_library(t.value); // block thread only
    } catch (const std::runtime_error& e) {
        d_logger->error("{} (refusing the stream)", e.what());
        d_refused = true;
        return WORK_DONE;
    }
    return sink_block::work(noutput_items, input_items, output_items);
}

double classifier_sink_impl::accuracy() const
{
    return d_core.locked([this] { return d_task.accuracy(); });
}

std::vector<std::vector<uint64_t>> classifier_sink_impl::confusion() const
{
    return d_core.locked([this] { return d_task.confusion(); });
}

} // namespace sems
} // namespace gr
