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

track_set draw_tracks(const frame_settings& fs,
                      const scene& sc,
                      const pilot_mask& mask,
                      uint64_t seed,
                      int64_t first_track,
                      int64_t count,
                      int frames,
                      const std::vector<std::string>& class_names)
{
    if (!sc.is_random() || !sc.random_settings()->tracks)
        throw std::invalid_argument("tracks: the scene draws a new target every frame (it needs random.tracks)");
    const int64_t np = mask.size();
    track_set t;
    t.obs = torch::zeros({ count, frames, np, 2 }, torch::kFloat);
    t.length = torch::zeros({ count }, torch::kLong);
    t.label = torch::zeros({ count }, torch::kLong);
    // The classifier's index of each class id of the scene's library.
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
    const auto flat = mask.flat_indices();
    auto* obs = reinterpret_cast<gr_complex*>(t.obs.data_ptr<float>());
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
                gr_complex* dst = obs + (i * frames + f) * np;
                for (int64_t k = 0; k < np; ++k)
                    dst[k] = grid[static_cast<size_t>(flat[static_cast<size_t>(k)])];
            }
        }
    });
    return t;
}

torch::Tensor observe_tracks(const track_set& t,
                             const pilot_mask& mask,
                             double snr_min_db,
                             double snr_max_db,
                             at::Generator gen)
{
    const int64_t count = t.size(), frames = t.obs.size(1), np = t.obs.size(2);
    const auto var = training::draw_noise_variance(count, snr_min_db, snr_max_db, gen); // the trainer's rule
    auto scale = torch::empty({ np }, torch::kFloat);
    for (int64_t k = 0; k < np; ++k)
        scale[k] = static_cast<float>(mask.noise_scale(static_cast<int>(k)));
    // σ/√2 per real dimension, σ/√p_k for pilot k.
    auto sigma = torch::sqrt(var / 2.0).view({ count, 1, 1, 1 }) * scale.view({ 1, 1, np, 1 });
    auto noise = torch::randn(t.obs.sizes(), gen, torch::kFloat) * sigma;
    auto valid = torch::arange(frames, torch::kLong).view({ 1, frames }) < t.length.view({ count, 1 });
    return t.obs + noise * valid.view({ count, frames, 1, 1 }).to(torch::kFloat);
}

} // namespace temporal
} // namespace sems
} // namespace gr
