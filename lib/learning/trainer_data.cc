// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the trainer's data set, drawn from THE channel model. */
#include "learning/trainer_data.h"
#include <gnuradio/sems/core/channel_model.h>
#include <algorithm>
#include <stdexcept>

namespace gr {
namespace sems {
namespace training {

namespace {
split slice(const torch::Tensor& h, const torch::Tensor& label, const torch::Tensor& delay, int64_t a, int64_t b)
{
    return { h.slice(0, a, b), label.slice(0, a, b), delay.slice(0, a, b) };
}
} // namespace

data_set make_data(const training_settings& s, const scene& sc)
{
    const auto& fs = s.frame;
    const int64_t count = s.frames, n = fs.n_symbols, m = fs.n_subcarriers;
    channel_model model(fs, sc, s.seed);
    std::vector<gr_complex> h(static_cast<size_t>(count * n * m));
    const auto truths = model.generate(count, h.data(), 0);

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
    // count x N x M complex -> count x 2 x N x M (real, imag)
    auto all = torch::from_blob(h.data(), { count, n, m, 2 }, torch::kFloat).permute({ 0, 3, 1, 2 }).contiguous();
    const int64_t n_train = count * 8 / 10, n_val = count / 10;
    d.train = slice(all, label, delay, 0, n_train);
    d.val = slice(all, label, delay, n_train, n_train + n_val);
    d.test = slice(all, label, delay, n_train + n_val, count);
    return d;
}

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

} // namespace training
} // namespace sems
} // namespace gr
