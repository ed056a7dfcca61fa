// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier's template bank — its class scores against the closed form
 * computed here in double precision, leave-one-out, the decoder with and without a bank, and
 * its settings' errors. */
#include "learning/networks/spectral_classifier_decoder.h"
#include "learning/networks/template_bank.h"
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

using namespace gr::sems;
using namespace gr::sems::nn;

namespace {
using cd = std::complex<double>;

// T x 2 x N_p (or B x 2 x N_p) float from complex vectors.
torch::Tensor to_tensor(const std::vector<std::vector<cd>>& v)
{
    const int64_t n = static_cast<int64_t>(v.size()), np = static_cast<int64_t>(v[0].size());
    auto t = torch::empty({ n, 2, np });
    auto a = t.accessor<float, 3>();
    for (int64_t i = 0; i < n; ++i)
        for (int64_t k = 0; k < np; ++k) {
            a[i][0][k] = static_cast<float>(v[i][k].real());
            a[i][1][k] = static_cast<float>(v[i][k].imag());
        }
    return t;
}

std::vector<cd> random_vector(std::mt19937& rng, int np, double scale = 1.0)
{
    std::normal_distribution<double> g(0.0, scale);
    std::vector<cd> v(np);
    for (auto& x : v)
        x = cd(g(rng), g(rng));
    return v;
}

// `count` random templates of N_p pilots, labelled 0, 1, ..., n_classes - 1 in turn.
struct labelled_templates {
    std::vector<std::vector<cd>> tmpl;
    std::vector<int> labels;
    torch::Tensor label_tensor() const { return torch::tensor(std::vector<int64_t>(labels.begin(), labels.end())); }
};
labelled_templates cyclic_templates(std::mt19937& rng, int count, int np, int n_classes)
{
    labelled_templates out;
    for (int t = 0; t < count; ++t) {
        out.tmpl.push_back(random_vector(rng, np));
        out.labels.push_back(t % n_classes);
    }
    return out;
}

// The class scores of template_bank.h written out: ρ_t = |yᴴt|²/(‖y‖²‖t‖²), β = N_p/(1 - max ρ)
// (1 - max ρ at least 1e-3), s_c = log mean_{t in c, t != left_out} exp(β ρ_t), normalised over
// the classes and floored at -30; then log(1 - max ρ + 1e-4).
std::vector<double> closed_form(const std::vector<cd>& y,
                                const std::vector<std::vector<cd>>& templates,
                                const std::vector<int>& labels,
                                int n_classes,
                                int left_out = -1,
                                double* beta_out = nullptr)
{
    const int np = static_cast<int>(y.size());
    double ey = 0.0;
    for (auto x : y)
        ey += std::norm(x);
    std::vector<double> rho(templates.size());
    double best = 0.0;
    for (size_t t = 0; t < templates.size(); ++t) {
        cd dot = 0.0;
        double et = 0.0;
        for (int k = 0; k < np; ++k) {
            dot += std::conj(y[k]) * templates[t][k];
            et += std::norm(templates[t][k]);
        }
        rho[t] = std::norm(dot) / (ey * et);
        if (static_cast<int>(t) != left_out)
            best = std::max(best, rho[t]);
    }
    const double beta = np / std::max(1.0 - best, 1e-3);
    if (beta_out)
        *beta_out = beta;
    std::vector<double> s(n_classes, -INFINITY);
    for (int c = 0; c < n_classes; ++c) {
        std::vector<double> a;
        for (size_t t = 0; t < templates.size(); ++t)
            if (labels[t] == c && static_cast<int>(t) != left_out)
                a.push_back(beta * rho[t]);
        if (a.empty())
            continue;
        const double m = *std::max_element(a.begin(), a.end());
        double sum = 0.0;
        for (double x : a)
            sum += std::exp(x - m);
        s[c] = m + std::log(sum / a.size());
    }
    double m = -INFINITY;
    for (double x : s)
        m = std::max(m, x);
    double z = 0.0;
    for (double x : s)
        z += std::isfinite(x) ? std::exp(x - m) : 0.0;
    std::vector<double> out;
    for (double x : s)
        out.push_back(std::max(x - (m + std::log(z)), -30.0));
    out.push_back(std::log(1.0 - best + 1e-4));
    return out;
}
} // namespace

class qa_learning_templates : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_learning_templates);
    CPPUNIT_TEST(scores_equal_the_closed_form);
    CPPUNIT_TEST(leave_one_out_equals_a_bank_without_the_frame);
    CPPUNIT_TEST(a_template_in_noise_is_found_at_every_gain_and_phase);
    CPPUNIT_TEST(decoder_bank_adds_nothing_until_filled_and_trained);
    CPPUNIT_TEST(bad_banks_and_settings_are_refused);
    CPPUNIT_TEST_SUITE_END();

    static constexpr int np = 12, n_classes = 3;

public:
    // Random frames against random templates of three classes (one class without templates:
    // its score is the floor), in noise from -20 to +40 dB.
    void scores_equal_the_closed_form()
    {
        std::mt19937 rng(7);
        std::vector<std::vector<cd>> tmpl;
        std::vector<int> labels;
        for (int t = 0; t < 40; ++t) {
            tmpl.push_back(random_vector(rng, np, 0.1 + t % 5));
            labels.push_back(t % 2 == 0 ? 2 : 0); // class 1 has none
        }
        template_bank_module bank(np, 40, n_classes);
        bank.eval();
        bank.set(to_tensor(tmpl), torch::tensor(std::vector<int64_t>(labels.begin(), labels.end())));
        CPPUNIT_ASSERT(bank.ready());
        std::vector<std::vector<cd>> frames;
        for (double snr_db : { -20.0, 0.0, 10.0, 40.0 })
            for (int t : { 3, 8 }) {
                auto y = tmpl[t];
                const auto n = random_vector(rng, np, std::sqrt(std::pow(10.0, -snr_db / 10.0)) * (0.1 + t % 5));
                for (int k = 0; k < np; ++k)
                    y[k] = y[k] * std::polar(2.5, 0.7 * t) + n[k];
                frames.push_back(y);
            }
        const auto s = bank.scores(to_tensor(frames)).to(torch::kDouble);
        CPPUNIT_ASSERT_EQUAL(int64_t(n_classes + 1), s.size(1));
        for (size_t f = 0; f < frames.size(); ++f) {
            double beta = 0.0;
            const auto want = closed_form(frames[f], tmpl, labels, n_classes, -1, &beta);
            // Float rounding of ρ (~1e-7) is multiplied by β (up to 1000 N_p).
            for (int c = 0; c <= n_classes; ++c)
                CPPUNIT_ASSERT_DOUBLES_EQUAL(want[c], s[f][c].item<double>(),
                                             1e-4 * std::max(1.0, std::abs(want[c])) + 1e-6 * beta);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-30.0, s[f][1].item<double>(), 0.0);
        }
    }

    // In training, a frame's own template is left out: its scores equal those of a bank
    // without that template; outside training, nothing is left out.
    void leave_one_out_equals_a_bank_without_the_frame()
    {
        std::mt19937 rng(11);
        const auto bank_frames = cyclic_templates(rng, 9, np, n_classes);
        const auto& tmpl = bank_frames.tmpl;
        const auto& labels = bank_frames.labels;
        template_bank_module bank(np, 9, n_classes);
        const auto row = bank.set(to_tensor(tmpl), bank_frames.label_tensor());
        const int own = 4; // the frame is template 4 itself (class 1)
        const auto frame = to_tensor({ tmpl[own], tmpl[own] });
        bank.train();
        bank.exclude(torch::tensor(std::vector<int64_t>{ row[own].item<int64_t>(), -1 }));
        const auto s = bank.scores(frame);
        const auto loo = closed_form(tmpl[own], tmpl, labels, n_classes, own);
        const auto all = closed_form(tmpl[own], tmpl, labels, n_classes);
        for (int c = 0; c <= n_classes; ++c) {
            CPPUNIT_ASSERT_DOUBLES_EQUAL(loo[c], s[0][c].item<double>(), 2e-3 * std::max(1.0, std::abs(loo[c])));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(all[c], s[1][c].item<double>(), 2e-3 * std::max(1.0, std::abs(all[c])));
        }
        // Its own template found: class 1 certain, and nothing left unexplained.
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, s[1][1].item<double>(), 1e-4);
        CPPUNIT_ASSERT(s[1][n_classes].item<double>() < std::log(2e-4));
        bank.eval(); // exclusions are read in training only
        const auto e = bank.scores(frame);
        CPPUNIT_ASSERT(torch::allclose(e[0], e[1]));
        // A bank of one frame left out entirely: every class at the floor, still finite.
        template_bank_module one(np, 1, n_classes);
        one.set(to_tensor({ tmpl[0] }), torch::tensor(std::vector<int64_t>{ 0 }));
        one.train();
        one.exclude(torch::tensor(std::vector<int64_t>{ 0 }));
        const auto f = one.scores(to_tensor({ tmpl[0] }));
        CPPUNIT_ASSERT(torch::isfinite(f).all().item<bool>());
    }

    // The class a frame's template belongs to scores highest whatever its complex gain
    // (1e-15 to 1e15, any phase), from 10 dB up.
    void a_template_in_noise_is_found_at_every_gain_and_phase()
    {
        std::mt19937 rng(3);
        const auto bank_frames = cyclic_templates(rng, 30, np, n_classes);
        const auto& tmpl = bank_frames.tmpl;
        const auto& labels = bank_frames.labels;
        template_bank_module bank(np, 30, n_classes);
        bank.eval();
        bank.set(to_tensor(tmpl), bank_frames.label_tensor());
        for (double gain : { 1e-15, 1e-3, 1.0, 1e15 })
            for (int t : { 0, 13, 29 }) {
                auto y = tmpl[t];
                const auto n = random_vector(rng, np, std::sqrt(0.1)); // 10 dB
                for (int k = 0; k < np; ++k)
                    y[k] = gain * (y[k] * std::polar(1.0, 2.0 * t) + n[k]);
                const auto s = bank.scores(to_tensor({ y }));
                CPPUNIT_ASSERT(torch::isfinite(s).all().item<bool>());
                CPPUNIT_ASSERT_EQUAL(int64_t(labels[t]), s[0].slice(0, 0, n_classes).argmax().item<int64_t>());
            }
        // A frame without energy matches nothing: finite, every class alike.
        const auto z = bank.scores(torch::zeros({ 1, 2, np }));
        CPPUNIT_ASSERT(torch::isfinite(z).all().item<bool>());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(z[0][0].item<double>(), z[0][2].item<double>(), 1e-6);
    }

    // A decoder with a bank computes what the same decoder without one does until the bank is
    // filled, and its joining layer starts at zero, so filling changes nothing either until it
    // trains; the bank's pilots are read in the mask's order from the whole or a compact grid.
    void decoder_bank_adds_nothing_until_filled_and_trained()
    {
        const int n = 8, m = 4, p = 8;
        classifier_settings s;
        s.n_classes = n_classes;
        s.chirp_bins = 0;
        s.range_bins = 0;
        torch::manual_seed(1);
        spectral_classifier_decoder_module plain(n, m, p, s);
        s.template_frames = 5;
        torch::manual_seed(1);
        spectral_classifier_decoder_module with_bank(n, m, p, s);
        plain.eval();
        with_bank.eval();
        auto mask = torch::zeros({ n, m });
        mask.select(1, 2).fill_(1.0f); // one subcarrier, every symbol
        const auto grid = torch::randn({ 3, 2, n, m }) * mask;
        const auto before = with_bank.forward(grid, mask).logits;
        CPPUNIT_ASSERT(torch::equal(plain.forward(grid, mask).logits, before));
        auto bank = with_bank.template_bank();
        CPPUNIT_ASSERT(bank && !bank->ready());
        const auto pilots = torch::randn({ 5, 2, n, m }).mul(mask).flatten(2).index_select(2, mask.flatten().nonzero().squeeze(1));
        bank->set(pilots, torch::tensor(std::vector<int64_t>{ 0, 1, 2, 0, 1 }));
        CPPUNIT_ASSERT(torch::equal(before, with_bank.forward(grid, mask).logits));
        {
            torch::NoGradGuard ng;
            for (auto& prm : bank->parameters())
                prm.fill_(0.25f);
        }
        const auto after = with_bank.forward(grid, mask).logits;
        CPPUNIT_ASSERT(!torch::allclose(before, after));
        // The same answer from the compact grid of the occupied subcarrier.
        with_bank.set_compact_columns({ 2 });
        const auto compact = with_bank.forward(grid.slice(3, 2, 3), mask.slice(1, 2, 3)).logits;
        CPPUNIT_ASSERT(torch::allclose(after, compact, 1e-5, 1e-5));
        // A mask of another pilot count than the bank's is refused.
        auto wrong = mask.clone();
        wrong[0][0] = 1.0f;
        CPPUNIT_ASSERT_THROW(with_bank.forward(grid * wrong, wrong), std::invalid_argument);
    }

    void bad_banks_and_settings_are_refused()
    {
        auto message = [](auto&& f) {
            try {
                f();
            } catch (const std::invalid_argument& e) {
                return std::string(e.what());
            }
            return std::string("(no error)");
        };
        const auto m1 = message([] { classifier_settings::from_json({ { "template_frames", -2 } }, "cls"); });
        CPPUNIT_ASSERT_MESSAGE(m1, m1.find("cls: template_frames") != std::string::npos);
        const auto m2 = message([] {
            classifier_settings::from_json({ { "architecture", "resnet" }, { "template_frames", 10 } }, "cls");
        });
        CPPUNIT_ASSERT_MESSAGE(m2, m2.find("template_frames") != std::string::npos && m2.find("spectral") != std::string::npos);
        // -1 is for the trainer to resolve, not a decoder's size.
        classifier_settings s;
        s.template_frames = -1;
        const auto m3 = message([&] { spectral_classifier_decoder_module(8, 4, 8, s); });
        CPPUNIT_ASSERT_MESSAGE(m3, m3.find("template_frames") != std::string::npos);
        const auto m6 = message([] { template_bank_module(1 << 20, 1 << 20, n_classes); });
        CPPUNIT_ASSERT_MESSAGE(m6, m6.find("exceed the limit") != std::string::npos);
        template_bank_module bank(np, 4, n_classes);
        const auto m4 = message([&] { bank.set(torch::zeros({ 3, 2, np }), torch::zeros({ 3 }, torch::kLong)); });
        CPPUNIT_ASSERT_MESSAGE(m4, m4.find("4 x 2 x 12") != std::string::npos);
        const auto m5 = message([&] { bank.set(torch::zeros({ 4, 2, np }), torch::tensor(std::vector<int64_t>{ 0, 1, 2, 3 })); });
        CPPUNIT_ASSERT_MESSAGE(m5, m5.find("label") != std::string::npos);
        // Legacy bundles: no key, no bank; the key is written only for a bank.
        CPPUNIT_ASSERT_EQUAL(0, classifier_settings::from_json(nlohmann::json::object(), "cls").template_frames);
        CPPUNIT_ASSERT(!classifier_settings{}.to_json().contains("template_frames"));
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_learning_templates);
