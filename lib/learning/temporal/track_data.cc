// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: tracks drawn alone from (seed, track index), kept as their pilots (see track_data.h). */
#include "learning/temporal/track_data.h"
#include "learning/training/trainer_data.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <ATen/Parallel.h>
#include <algorithm>
#include <stdexcept>

namespace gr {
namespace sems {
namespace temporal {

namespace {
// The classifier's index of each class id of the scene's library; a class the scene draws
// and the classifier lacks is refused.
std::vector<int64_t> class_index(const scene& sc, const std::vector<std::string>& class_names)
{
    if (!sc.is_random() || !sc.random_settings()->tracks)
        throw std::invalid_argument("tracks: the scene draws a new target every frame (it needs random.tracks)");
    std::vector<int64_t> index_of(static_cast<size_t>(sc.library().size()), -1);
    for (int c = 0; c < sc.library().size(); ++c) {
        const auto it = std::find(class_names.begin(), class_names.end(), sc.library().at(c).name);
        if (it != class_names.end())
            index_of[static_cast<size_t>(c)] = it - class_names.begin();
    }
    for (auto c : sc.label_classes())
        if (index_of[static_cast<size_t>(c)] < 0)
            throw std::invalid_argument("tracks: the scene draws class \"" + sc.class_name(c) +
                                        "\", which the classifier does not have");
    return index_of;
}

// Every frame of tracks first_track .. + count − 1 (at most `frames` each), in parallel:
// visit(i, t, grid) with the frame's noiseless N x M grid; lengths and labels filled in.
template <typename Visit>
void for_each_frame(const frame_settings& fs,
                    const scene& sc,
                    uint64_t seed,
                    int64_t first_track,
                    int64_t count,
                    int frames,
                    const std::vector<int64_t>& index_of,
                    track_set& t,
                    Visit visit)
{
    t.length = torch::zeros({ count }, torch::kLong);
    t.label = torch::zeros({ count }, torch::kLong);
    auto* length = t.length.data_ptr<int64_t>();
    auto* label = t.label.data_ptr<int64_t>();
    at::parallel_for(0, count, 4, [&](int64_t a, int64_t b) {
        channel_model cm(fs, sc, seed); // one per thread: a track is drawn from (seed, index) alone
        std::vector<gr_complex> grid(static_cast<size_t>(fs.grid_size()));
        frame_realization r;
        for (int64_t i = a; i < b; ++i) {
            const int len = std::min(frames, cm.begin_track(static_cast<uint64_t>(first_track + i)));
            length[i] = len;
            for (int f = 0; f < len; ++f) {
                cm.draw(static_cast<uint64_t>(f), r);
                if (f == 0)
                    label[i] = index_of[static_cast<size_t>(r.truth.class_id)];
                cm.factors(r, 0).fill(grid.data()); // the track's own clock
                visit(i, f, grid.data());
            }
        }
    });
}
} // namespace

track_set draw_tracks(const frame_settings& fs,
                      const scene& sc,
                      const super_frame_mask& mask,
                      uint64_t seed,
                      int64_t first_track,
                      int64_t count,
                      int frames,
                      const std::vector<std::string>& class_names)
{
    const auto index_of = class_index(sc, class_names);
    const int64_t np = mask.pilots_per_frame();
    const int64_t n_sets = mask.n_frames();
    track_set t;
    t.obs = torch::zeros({ count, frames, np, 2 }, torch::kFloat);
    t.set = torch::zeros({ count, frames }, torch::kInt);
    std::vector<std::vector<int>> flat;
    for (const auto& m : mask.sets())
        flat.push_back(m.flat_indices());
    auto* obs = reinterpret_cast<gr_complex*>(t.obs.data_ptr<float>());
    auto* set = t.set.data_ptr<int>();
    for (int64_t i = 0; i < count; ++i)
        for (int f = 0; f < frames; ++f)
            set[i * frames + f] = static_cast<int>((first_track + i + f) % n_sets);
    for_each_frame(fs, sc, seed, first_track, count, frames, index_of, t,
                   [&](int64_t i, int f, const gr_complex* grid) {
                       const auto& idx = flat[static_cast<size_t>(set[i * frames + f])];
                       gr_complex* dst = obs + (i * frames + f) * np;
                       for (int64_t k = 0; k < np; ++k)
                           dst[k] = grid[static_cast<size_t>(idx[static_cast<size_t>(k)])];
                   });
    return t;
}

track_set draw_track_grids(const frame_settings& fs,
                           const scene& sc,
                           uint64_t seed,
                           int64_t first_track,
                           int64_t count,
                           int frames,
                           const std::vector<std::string>& class_names)
{
    const auto index_of = class_index(sc, class_names);
    const int64_t n = fs.n_symbols, m = fs.n_subcarriers;
    track_set t;
    t.obs = torch::zeros({ count, frames, 2, n, m }, torch::kFloat);
    t.set = torch::zeros({ count, frames }, torch::kInt);
    auto* obs = t.obs.data_ptr<float>();
    for_each_frame(fs, sc, seed, first_track, count, frames, index_of, t,
                   [&](int64_t i, int f, const gr_complex* grid) {
                       float* re = obs + (i * frames + f) * 2 * n * m;
                       float* im = re + n * m;
                       for (int64_t e = 0; e < n * m; ++e) {
                           re[e] = grid[e].real();
                           im[e] = grid[e].imag();
                       }
                   });
    return t;
}

torch::Tensor observe_tracks(const track_set& t,
                             const super_frame_mask& mask,
                             double snr_min_db,
                             double snr_max_db,
                             at::Generator gen)
{
    const int64_t count = t.size(), frames = t.obs.size(1), np = t.obs.size(2);
    const auto var = training::draw_noise_variance(count, snr_min_db, snr_max_db, gen); // the trainer's rule
    const int64_t n_sets = mask.n_frames();
    auto scale = torch::empty({ n_sets, np }, torch::kFloat);
    for (int64_t f = 0; f < n_sets; ++f)
        for (int64_t k = 0; k < np; ++k)
            scale[f][k] = static_cast<float>(mask.set(static_cast<int>(f)).noise_scale(static_cast<int>(k)));
    // σ/√2 per real dimension, σ/√p_k for pilot k of the frame's set.
    auto frame_scale = scale.index_select(0, t.set.flatten().to(torch::kLong)).view({ count, frames, np, 1 });
    auto sigma = torch::sqrt(var / 2.0).view({ count, 1, 1, 1 }) * frame_scale;
    auto noise = torch::randn(t.obs.sizes(), gen, torch::kFloat) * sigma;
    auto valid = torch::arange(frames, torch::kLong).view({ 1, frames }) < t.length.view({ count, 1 });
    return t.obs + noise * valid.view({ count, frames, 1, 1 }).to(torch::kFloat);
}

} // namespace temporal
} // namespace sems
} // namespace gr
