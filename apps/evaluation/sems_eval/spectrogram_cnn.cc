// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 8: the Perfect-CSI spectrogram CNN (see spectrogram_cnn.h). */
#include "spectrogram_cnn.h"
#include <torch/torch.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <iomanip>
#include <ostream>
#include <stdexcept>

namespace sems_eval {

std::vector<float> track_spectrogram(const gr::sems::frame_settings& fs, const gr_complex* grids, int frames, int len)
{
    const int n = fs.n_symbols, m = fs.n_subcarriers, rows = n + m;
    std::vector<float> img(size_t(rows) * frames, 0.0f);
    std::vector<double> win(n);
    for (int i = 0; i < n; ++i)
        win[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * (i + 0.5) / n); // Hann sampled at mid-points: no zero end symbols
    // Twiddles of Doppler bin q - N/2 (centred) at symbol s, with the window folded in; and of
    // range bin d at subcarrier k.
    std::vector<std::complex<double>> tw(size_t(n) * n), tr(size_t(m) * m);
    for (int q = 0; q < n; ++q)
        for (int s = 0; s < n; ++s)
            tw[size_t(q) * n + s] = win[s] * std::polar(1.0, -2.0 * M_PI * (q - n / 2) * s / n);
    for (int d = 0; d < m; ++d)
        for (int k = 0; k < m; ++k)
            tr[size_t(d) * m + k] = std::polar(1.0, 2.0 * M_PI * d * k / m);
    std::vector<double> p(rows);
    auto put = [&](int row0, int count, int f) { // normalised dB of p[row0 .. row0 + count) into column f
        double total = 0.0;
        for (int q = 0; q < count; ++q)
            total += p[row0 + q];
        for (int q = 0; q < count; ++q) {
            const double db = total > 0.0 ? 10.0 * std::log10(std::max(p[row0 + q] / total, 1e-6)) : -60.0;
            img[size_t(row0 + q) * frames + f] = static_cast<float>(1.0 + db / 60.0); // [0, 1]: -60 dB .. 0 dB
        }
    };
    for (int f = 0; f < len; ++f) {
        const gr_complex* g = grids + size_t(f) * n * m;
        std::fill(p.begin(), p.end(), 0.0);
        for (int sc = 0; sc < m; ++sc)
            for (int q = 0; q < n; ++q) {
                std::complex<double> acc = 0.0;
                const std::complex<double>* t = tw.data() + size_t(q) * n;
                for (int s = 0; s < n; ++s)
                    acc += t[s] * std::complex<double>(g[size_t(s) * m + sc]);
                p[q] += std::norm(acc);
            }
        for (int s = 0; s < n; ++s)
            for (int d = 0; d < m; ++d) {
                std::complex<double> acc = 0.0;
                const std::complex<double>* t = tr.data() + size_t(d) * m;
                for (int k = 0; k < m; ++k)
                    acc += t[k] * std::complex<double>(g[size_t(s) * m + k]);
                p[n + d] += std::norm(acc);
            }
        put(0, n, f);
        put(n, m, f);
    }
    return img;
}

namespace {

struct spectrogram_netImpl : torch::nn::Module {
    spectrogram_netImpl(int bins, int classes)
        : c1(register_module("c1", torch::nn::Conv2d(torch::nn::Conv2dOptions(1, 16, 3).padding(1)))),
          c2(register_module("c2", torch::nn::Conv2d(torch::nn::Conv2dOptions(16, 32, 3).padding(1)))),
          c3(register_module("c3", torch::nn::Conv2d(torch::nn::Conv2dOptions(32, 32, 3).padding(1)))),
          b1(register_module("b1", torch::nn::BatchNorm2d(16))),
          b2(register_module("b2", torch::nn::BatchNorm2d(32))),
          b3(register_module("b3", torch::nn::BatchNorm2d(32))),
          fc1(register_module("fc1", torch::nn::Linear(32 * (bins / 4), 128))),
          fc2(register_module("fc2", torch::nn::Linear(128, classes)))
    {
    }
    // x: B x 1 x D x K with columns past t zero; valid: B x K (1 inside the first t).
    torch::Tensor forward(torch::Tensor x, const torch::Tensor& valid)
    {
        namespace F = torch::nn::functional;
        const auto pool = F::MaxPool2dFuncOptions({ 2, 1 }); // over Doppler only: time stays causal
        x = F::max_pool2d(torch::relu(b1(c1(x))), pool);
        x = F::max_pool2d(torch::relu(b2(c2(x))), pool);
        x = torch::relu(b3(c3(x)));                                  // B x 32 x D/4 x K
        x = x.flatten(1, 2).transpose(1, 2);                         // B x K x (32 D/4)
        const auto v = valid.unsqueeze(-1).to(x.dtype());
        x = (x * v).sum(1) / v.sum(1).clamp_min(1.0);               // mean over the frames given
        return fc2(torch::relu(fc1(x)));
    }
    torch::nn::Conv2d c1, c2, c3;
    torch::nn::BatchNorm2d b1, b2, b3;
    torch::nn::Linear fc1, fc2;
};
TORCH_MODULE(spectrogram_net);

} // namespace

struct spectrogram_cnn::impl {
    int bins, frames, classes, threads;
    uint64_t seed;
    spectrogram_net model{ nullptr };

    torch::Tensor batch(const std::vector<float>& images, const std::vector<int64_t>& rows,
                        const std::vector<int>& cut, torch::Tensor& valid) const
    {
        const int64_t b = static_cast<int64_t>(rows.size());
        auto x = torch::zeros({ b, 1, bins, frames });
        valid = torch::zeros({ b, frames });
        auto* xp = x.data_ptr<float>();
        auto* vp = valid.data_ptr<float>();
        for (int64_t i = 0; i < b; ++i) {
            const float* src = images.data() + size_t(rows[i]) * bins * frames;
            for (int d = 0; d < bins; ++d)
                std::copy(src + size_t(d) * frames, src + size_t(d) * frames + cut[i], xp + (i * bins + d) * frames);
            std::fill(vp + i * frames, vp + i * frames + cut[i], 1.0f);
        }
        return x;
    }
};

spectrogram_cnn::spectrogram_cnn(int rows, int frames, int classes, uint64_t seed, int threads)
    : d_impl(std::make_unique<impl>())
{
    if (rows < 4 || rows % 4 || frames < 1 || classes < 2)
        throw std::invalid_argument("spectrogram CNN: needs image rows (N + M) a multiple of 4, frames >= 1, classes >= 2");
    d_impl->bins = rows;
    d_impl->frames = frames;
    d_impl->classes = classes;
    d_impl->seed = seed;
    d_impl->threads = threads;
    torch::manual_seed(seed);
    d_impl->model = spectrogram_net(rows, classes);
}

spectrogram_cnn::~spectrogram_cnn() = default;

void spectrogram_cnn::train(const std::vector<float>& images, const std::vector<int>& length,
                            const std::vector<int>& label, int epochs, std::ostream& log)
{
    auto& d = *d_impl;
    at::set_num_threads(d.threads);
    const int64_t count = static_cast<int64_t>(label.size());
    const int64_t n_val = std::max<int64_t>(1, count / 10), n_train = count - n_val;
    if (n_train < 1)
        throw std::invalid_argument("spectrogram CNN: too few training tracks");
    torch::optim::AdamW opt(d.model->parameters(), torch::optim::AdamWOptions(2e-3).weight_decay(1e-3));
    std::mt19937_64 gen(d.seed ^ 0x5bec7c22ULL);
    // Validation at fixed cuts (each track at a length of its own, drawn once).
    std::vector<int64_t> val_rows;
    std::vector<int> val_cut;
    for (int64_t i = n_train; i < count; ++i) {
        val_rows.push_back(i);
        val_cut.push_back(1 + static_cast<int>(gen() % uint64_t(length[i])));
    }
    std::vector<torch::Tensor> best;
    double best_acc = -1.0;
    std::vector<int64_t> order(n_train);
    for (int64_t i = 0; i < n_train; ++i)
        order[i] = i;
    const double lr0 = 2e-3;
    for (int epoch = 1; epoch <= epochs; ++epoch) {
        const double lr = lr0 * 0.5 * (1.0 + std::cos(M_PI * (epoch - 1) / epochs)); // cosine decay
        for (auto& group : opt.param_groups())
            static_cast<torch::optim::AdamWOptions&>(group.options()).lr(lr);
        d.model->train();
        std::shuffle(order.begin(), order.end(), gen);
        double loss_sum = 0.0;
        int steps = 0;
        for (int64_t a = 0; a < n_train; a += 64) {
            std::vector<int64_t> rows(order.begin() + a, order.begin() + std::min(n_train, a + 64));
            std::vector<int> cut;
            auto y = torch::empty({ int64_t(rows.size()) }, torch::kLong);
            for (size_t i = 0; i < rows.size(); ++i) {
                cut.push_back(1 + static_cast<int>(gen() % uint64_t(length[rows[i]])));
                y[i] = label[rows[i]];
            }
            torch::Tensor valid;
            const auto x = d.batch(images, rows, cut, valid);
            auto loss = torch::nn::functional::cross_entropy(d.model->forward(x, valid), y);
            opt.zero_grad();
            loss.backward();
            opt.step();
            loss_sum += loss.item<double>();
            ++steps;
        }
        torch::NoGradGuard ng;
        d.model->eval();
        torch::Tensor valid;
        const auto x = d.batch(images, val_rows, val_cut, valid);
        const auto pred = d.model->forward(x, valid).argmax(1);
        int64_t ok = 0;
        for (size_t i = 0; i < val_rows.size(); ++i)
            ok += pred[i].item<int64_t>() == label[val_rows[i]];
        const double acc = double(ok) / double(val_rows.size());
        log << "    spectrogram CNN epoch " << epoch << "/" << epochs << ": loss " << std::setprecision(4)
            << loss_sum / std::max(1, steps) << ", validation accuracy " << acc << std::endl;
        if (acc > best_acc) {
            best_acc = acc;
            best.clear();
            for (const auto& p : d.model->parameters())
                best.push_back(p.detach().clone());
        }
    }
    torch::NoGradGuard ng;
    auto params = d.model->parameters();
    for (size_t i = 0; i < params.size(); ++i)
        params[i].copy_(best[i]);
    d.model->eval();
}

std::vector<int> spectrogram_cnn::predict(const std::vector<float>& images, const std::vector<int>& length, int t) const
{
    auto& d = *d_impl;
    at::set_num_threads(d.threads);
    torch::NoGradGuard ng;
    d.model->eval();
    const int64_t count = static_cast<int64_t>(length.size());
    std::vector<int> out(count, -1);
    for (int64_t a = 0; a < count; a += 256) {
        std::vector<int64_t> rows;
        std::vector<int> cut;
        for (int64_t i = a; i < std::min(count, a + 256); ++i)
            if (length[i] >= t) {
                rows.push_back(i);
                cut.push_back(t);
            }
        if (rows.empty())
            continue;
        torch::Tensor valid;
        const auto x = d.batch(images, rows, cut, valid);
        const auto pred = d.model->forward(x, valid).argmax(1).contiguous();
        for (size_t i = 0; i < rows.size(); ++i)
            out[rows[i]] = static_cast<int>(pred[i].item<int64_t>());
    }
    return out;
}

} // namespace sems_eval
