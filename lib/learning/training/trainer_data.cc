// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the trainer's data set, drawn from THE channel model. */
#include "learning/training/trainer_data.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/radio/front_end_frame.h>
#include <ATen/Parallel.h>
#include <algorithm>
#include <list>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <unistd.h>

namespace gr {
namespace sems {
namespace training {

namespace {
// One frame's noiseless channel held as floats: 2·N·M of them.
double frame_bytes(const frame_settings& fs) { return 2.0 * fs.n_symbols * fs.n_subcarriers * sizeof(float); }
// The frames of the 8:1:1 split that train (the rest: validation, then test).
int64_t training_frames(int64_t count) { return count * 8 / 10; }
} // namespace

// Streamed frames: each frame's drawn paths, and its H computed from them when asked.
// channel_model::generate() computes a frame as factors(draw(i), i·N).fill(), and the factors
// are a function of the paths alone: the same bits as the held frame.
class frame_stream
{
public:
    frame_stream(const frame_settings& fs, std::vector<frame_realization> frames)
        : d_fs(fs), d_frames(std::move(frames))
    {
    }
    int64_t size() const { return static_cast<int64_t>(d_frames.size()); }
    // What the frames would take held.
    double bytes() const { return double(size()) * frame_bytes(d_fs); }
    // Frames idx as count x 2 x N x M.
    torch::Tensor frames(const torch::Tensor& idx) const
    {
        const auto ix = idx.to(torch::kLong).contiguous();
        const int64_t count = ix.size(0), n = d_fs.n_symbols, m = d_fs.n_subcarriers;
        const int64_t* pi = ix.data_ptr<int64_t>();
        for (int64_t i = 0; i < count; ++i)
            if (pi[i] < 0 || pi[i] >= size())
                throw std::logic_error("streamed training frames: frame " + std::to_string(pi[i]) + " of " +
                                       std::to_string(size()));
        auto out = torch::empty({ count, n, m, 2 }, torch::kFloat);
        auto* dst = reinterpret_cast<gr_complex*>(out.data_ptr<float>());
        at::parallel_for(0, count, 1, [&](int64_t a, int64_t b) {
            for (int64_t i = a; i < b; ++i) {
                const uint64_t f = static_cast<uint64_t>(pi[i]);
                frame_channel(d_fs, d_frames[f], f * static_cast<uint64_t>(n)).fill(dst + i * n * m);
            }
        });
        return out.permute({ 0, 3, 1, 2 }).contiguous();
    }

private:
    frame_settings d_fs;
    std::vector<frame_realization> d_frames; // training frame i (frame i of the data set)
};

torch::Tensor split::frames(const torch::Tensor& idx) const
{
    return stream ? stream->frames(idx) : h.index_select(0, idx);
}

torch::Tensor split::pilots(int64_t count, const torch::Tensor& flat) const
{
    if (!stream)
        return h.slice(0, 0, count).flatten(2).index_select(2, flat);
    auto out = torch::empty({ count, 2, flat.size(0) }, torch::kFloat);
    constexpr int64_t step = 256;
    for (int64_t a = 0; a < count; a += step) {
        const int64_t b = std::min(count, a + step);
        out.slice(0, a, b).copy_(stream->frames(torch::arange(a, b, torch::kLong)).flatten(2).index_select(2, flat));
    }
    return out;
}

double split::held_bytes() const
{
    return h.defined() ? static_cast<double>(h.nbytes()) : stream ? stream->bytes() : 0.0;
}

namespace {
// Whether s's training frames are streamed. "auto": beyond a quarter of the memory, since the
// validation and test frames add a quarter of the training frames' size and a batch of large
// frames takes gigabytes (30 000 nr_30khz frames held: over 20 GiB at the peak).
bool streams(const training_settings& s)
{
    if (s.training_data != "auto")
        return s.training_data == "stream";
    const double memory = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
    return memory > 0.0 && double(training_frames(s.frames)) * frame_bytes(s.frame) > 0.25 * memory;
}

// The data set, its training frames streamed when `streamed`.
data_set draw_data(const training_settings& s, const scene& sc, bool streamed);

// The last few data sets drawn in this process, by what determines them (frame, scene with its
// class library, frame count, seed, streamed or held). An evaluation trains many networks per
// training seed on the same frames; they are drawn once. The tensors are shared and never
// written in place.
class data_cache
{
public:
    data_set get(const training_settings& s, const scene& sc)
    {
        const bool stream = streams(s);
        const std::string key = s.frame.to_json().dump() + "|" + sc.to_json_string() + "|" +
                                sc.library().to_json().dump() + "|" + std::to_string(s.frames) + "|" +
                                std::to_string(s.seed) + "|" + std::to_string(stream);
        std::lock_guard<std::mutex> lock(d_mutex);
        for (auto it = d_entries.begin(); it != d_entries.end(); ++it)
            if (it->first == key) {
                d_entries.splice(d_entries.begin(), d_entries, it); // most recent first
                return it->second;
            }
        data_set d = draw_data(s, sc, stream);
        d_entries.emplace_front(key, d);
        size_t bytes = 0;
        for (auto it = d_entries.begin(); it != d_entries.end(); ++it) {
            bytes += bytes_of(it->second);
            if (bytes > max_bytes || std::distance(d_entries.begin(), it) >= max_entries) {
                d_entries.erase(it == d_entries.begin() ? std::next(it) : it, d_entries.end());
                break;
            }
        }
        return d;
    }

private:
    static size_t bytes_of(const data_set& d)
    {
        auto held = [](const split& p) { return p.h.defined() ? p.h.nbytes() : size_t(0); };
        return held(d.train) + held(d.val) + held(d.test);
    }
    static constexpr size_t max_bytes = size_t(2) << 30; // 2 GiB: four paper-frame sets of 30 000 frames
    static constexpr long max_entries = 4;
    std::mutex d_mutex;
    std::list<std::pair<std::string, data_set>> d_entries;
};
} // namespace

data_set make_data(const training_settings& s, const scene& sc)
{
    static data_cache cache;
    return cache.get(s, sc);
}

namespace {
data_set draw_data(const training_settings& s, const scene& sc, bool streamed)
{
    const auto& fs = s.frame;
    const int64_t count = s.frames, n = fs.n_symbols, m = fs.n_subcarriers;
    const int64_t n_train = training_frames(count), n_val = count / 10;
    channel_model model(fs, sc, s.seed);
    std::vector<frame_truth> truths;
    truths.reserve(static_cast<size_t>(count));
    // Streamed: the training frames' paths only (the model draws frame after frame, so they are
    // drawn first, as generate() would); their H is computed per batch.
    std::shared_ptr<const frame_stream> stream;
    int64_t first_held = 0;
    if (streamed) {
        std::vector<frame_realization> drawn;
        drawn.reserve(static_cast<size_t>(n_train));
        for (int64_t i = 0; i < n_train; ++i) {
            drawn.push_back(model.draw(static_cast<uint64_t>(i)));
            truths.push_back(drawn.back().truth);
        }
        stream = std::make_shared<frame_stream>(fs, std::move(drawn));
        first_held = n_train;
    }
    // count x N x M complex -> count x 2 x N x M (real, imag), drawn in chunks of consecutive
    // frames (the same frames as one call: the model draws frame after frame) so the set is
    // held once, not twice: 30 000 NR-sized frames (14 x 4 096) are 13.8 GB.
    auto held = torch::empty({ count - first_held, 2, n, m }, torch::kFloat);
    const int64_t chunk = std::max<int64_t>(1, std::min<int64_t>(count, int64_t((64 << 20) / frame_bytes(fs))));
    std::vector<gr_complex> h(static_cast<size_t>(chunk * n * m));
    for (int64_t first = first_held; first < count; first += chunk) {
        const int64_t k = std::min(chunk, count - first);
        const auto part = model.generate(static_cast<size_t>(k), h.data(), static_cast<uint64_t>(first));
        truths.insert(truths.end(), part.begin(), part.end());
        held.slice(0, first - first_held, first - first_held + k)
            .copy_(torch::from_blob(h.data(), { k, n, m, 2 }, torch::kFloat).permute({ 0, 3, 1, 2 }));
    }

    data_set d;
    const auto classes = sc.label_classes();
    for (auto c : classes)
        d.class_names.push_back(sc.class_name(c));
    auto label = torch::empty({ count }, torch::kLong);
    auto delay = torch::empty({ count }, torch::kFloat);
    d.delay_min = 1e300;
    d.delay_max = -1e300;
    for (int64_t i = 0; i < count; ++i) {
        const auto& t = truths[i];
        const auto it = std::find(classes.begin(), classes.end(), static_cast<target_class>(t.class_id));
        if (it == classes.end()) // never labelled 0 silently: the scene and its labels disagree
            throw std::logic_error("training data: frame " + std::to_string(i) + " has target class " +
                                   std::to_string(t.class_id) + ", which is not among the scene's label classes");
        label[i] = static_cast<int64_t>(it - classes.begin());
        delay[i] = static_cast<float>(t.delay_index);
        d.delay_min = std::min(d.delay_min, t.delay_index);
        d.delay_max = std::max(d.delay_max, t.delay_index);
    }
    // Frames [a, b), held: row i of `held` is frame first_held + i.
    auto rows = [&](int64_t a, int64_t b) {
        return split{ held.slice(0, a - first_held, b - first_held), label.slice(0, a, b), delay.slice(0, a, b), nullptr };
    };
    if (stream)
        d.train = split{ torch::Tensor(), label.slice(0, 0, n_train), delay.slice(0, 0, n_train), stream };
    else
        d.train = rows(0, n_train);
    d.val = rows(n_train, n_train + n_val);
    d.test = rows(n_train + n_val, count);
    return d;
}
} // namespace

torch::Tensor draw_noise_variance(int64_t count, double lo, double hi, c10::optional<at::Generator> gen)
{
    auto u = torch::rand({ count }, gen, torch::kDouble);
    auto var = torch::empty({ count }, torch::kFloat);
    auto pu = u.accessor<double, 1>();
    for (int64_t i = 0; i < count; ++i)
        var[i] = static_cast<float>(channel_model::noise_variance(lo == hi ? lo : lo + (hi - lo) * pu[i]));
    return var;
}

torch::Tensor add_noise(const torch::Tensor& h, const torch::Tensor& var, c10::optional<at::Generator> gen)
{
    auto noise = torch::randn(h.sizes(), gen, h.options());
    return h + noise * torch::sqrt(var / 2.0).view({ -1, 1, 1, 1 });
}

namespace {
// This thread's model of the radio, kept across batches: its FFT plans take milliseconds to
// make. observe() keeps no state between frames, so reusing it changes no observation.
front_end_frame& thread_radio(const frame_settings& fs, const front_end_settings& radio)
{
    thread_local std::unique_ptr<front_end_frame> model;
    thread_local frame_settings model_frame;
    thread_local front_end_settings model_radio;
    if (!model || model_frame != fs || !(model_radio == radio)) {
        model = std::make_unique<front_end_frame>(fs, radio);
        model_frame = fs;
        model_radio = radio;
    }
    return *model;
}
} // namespace

torch::Tensor observe(const torch::Tensor& h,
                      const torch::Tensor& var,
                      const torch::Tensor& delay,
                      const training_settings& s,
                      c10::optional<at::Generator> gen)
{
    if (!s.radio || s.radio->is_ideal()) // the ideal radio is the trainer's own model, bit for bit
        return add_noise(h, var, gen);
    const int64_t count = h.size(0), n = h.size(2), m = h.size(3);
    // One seed per frame, drawn first: the same observations whatever the thread count.
    const auto seeds = torch::randint(0, int64_t(1) << 62, { count }, gen, torch::kLong);
    // Frames as N x M complex (real, imag interleaved), observed, and back to the planes.
    const auto in = h.permute({ 0, 2, 3, 1 }).contiguous();
    auto out = torch::empty_like(in);
    const auto pv = var.to(torch::kDouble).contiguous(), pd = delay.to(torch::kDouble).contiguous();
    const double* v = pv.data_ptr<double>();
    const double* dl = pd.data_ptr<double>();
    const int64_t* sd = seeds.data_ptr<int64_t>();
    const auto* src = reinterpret_cast<const gr_complex*>(in.data_ptr<float>());
    auto* dst = reinterpret_cast<gr_complex*>(out.data_ptr<float>());
    at::parallel_for(0, count, 16, [&](int64_t a, int64_t b) {
        front_end_frame& radio = thread_radio(s.frame, *s.radio);
        for (int64_t i = a; i < b; ++i)
            radio.observe(src + i * n * m, dl[i], v[i], static_cast<uint64_t>(sd[i]), dst + i * n * m);
    });
    return out.permute({ 0, 3, 1, 2 }).contiguous();
}

} // namespace training
} // namespace sems
} // namespace gr
