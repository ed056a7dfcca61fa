// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the learned position decoder — the angle network's spectrum peaks where the
 * beamforming closed form says, a tiny seeded run writes a position bundle that loads back and
 * finds a noiseless target's azimuth and delay, and bad input, bundles and settings are
 * refused by name. */
#include "learning/array/angle_network.h"
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/array/position_trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

using namespace gr::sems;
using gr::sems::qa::assert_error;
namespace fsys = std::filesystem;

namespace {

// One tiny position bundle on the shipped delay_single bundle, shared by the tests.
const position_training_result& shared_position_run()
{
    static std::unique_ptr<position_training_result> r;
    if (!r) {
        position_training_settings s;
        s.delay_bundle = qa::models_dir() + "delay_single";
        s.array = "ula8_3g";
        s.frames = 400;
        s.epochs = 2;
        s.batch = 64;
        s.angle.grid = 64;
        s.angle.channels = 8;
        s.angle.blocks = 2;
        s.eval_snr_db = { 30.0 };
        s.seed = 3;
        s.threads = 1;
        s.verbose = false;
        s.out_dir = qa::temp_dir("position", "bundle");
        r = std::make_unique<position_training_result>(train_position(s, nullptr));
    }
    return *r;
}

// A noiseless frame of one car at `azimuth` through the bundle's mask, element-major.
std::vector<gr_complex> one_target(const model_bundle& b, const array_geometry& a, double azimuth, double* delay_index)
{
    target_spec t;
    t.cls = target_class::car;
    t.range_m = 80.0;
    t.velocity_mps = 6.0;
    t.azimuth_rad = azimuth;
    channel_model cm(b.frame, scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a), 5);
    const auto r = cm.draw(0);
    *delay_index = r.truth.delay_index;
    std::vector<gr_complex> h(size_t(b.frame.grid_size())), out;
    for (int e = 0; e < cm.n_elements(); ++e) {
        cm.factors(r, 0, e).fill(h.data());
        for (int i : b.mask.flat_indices())
            out.push_back(h[size_t(i)]);
    }
    return out;
}

} // namespace

class qa_position : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_position);
    CPPUNIT_TEST(the_spectrum_peaks_at_the_beamforming_closed_form);
    CPPUNIT_TEST(a_trained_bundle_finds_a_noiseless_target);
    CPPUNIT_TEST(bad_input_bundles_and_settings_are_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    // The network's first feature row is P(φ_q)/max P, P(φ) = Σ_p |a(φ)ᴴ y_p|² / ‖a‖² written
    // out here for a plane wave on a 4-element half-wavelength ULA: y_kp = exp(jπ k sin φ_0)·c_p,
    // so P(φ) ∝ |Σ_k exp(jπ k (sin φ_0 − sin φ))|², which peaks at φ_0.
    void the_spectrum_peaks_at_the_beamforming_closed_form()
    {
        const double lambda = 0.1;
        const auto a = array_geometry::ula(4, 0.5 * lambda);
        nn::angle_settings s;
        s.grid = 41;
        s.azimuth_min_rad = -1.0;
        s.azimuth_max_rad = 1.0;
        nn::angle_network net(a, lambda, s);
        const double phi0 = -1.0 + 2.0 * 27 / 40; // grid point 27
        auto y = torch::zeros({ 1, 4, 3, 2 });
        const double c[3][2] = { { 1.0, 0.0 }, { 0.0, -2.0 }, { 0.5, 0.5 } };
        for (int k = 0; k < 4; ++k) {
            const double y_k = (k - 1.5) * 0.5 * lambda; // ula() centres the elements
            const std::complex<double> ph = std::exp(std::complex<double>(0.0, 2.0 * M_PI / lambda * y_k * std::sin(phi0)));
            for (int p = 0; p < 3; ++p) {
                const auto v = ph * std::complex<double>(c[p][0], c[p][1]);
                y[0][k][p][0] = float(v.real());
                y[0][k][p][1] = float(v.imag());
            }
        }
        const auto f = net->features(y);
        CPPUNIT_ASSERT_EQUAL(int64_t(27), f[0][0].argmax().item<int64_t>());
        for (int q = 0; q < s.grid; ++q) {
            const double phi = -1.0 + 2.0 * q / 40;
            std::complex<double> sum = 0.0;
            for (int k = 0; k < 4; ++k)
                sum += std::exp(std::complex<double>(0.0, M_PI * (k - 1.5) * (std::sin(phi0) - std::sin(phi))));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::norm(sum) / 16.0, f[0][0][q].item<double>(), 1e-5);
        }
    }

    // The tiny run's bundle: written with its record, loaded back, and on noiseless frames
    // (where the polish is the spectrum's maximum) within the narrowband steering's error of the
    // truth, its delay within half an index; the test figures are recorded per SNR.
    void a_trained_bundle_finds_a_noiseless_target()
    {
        const auto& r = shared_position_run();
        const auto b = model_bundle::load(r.bundle.directory);
        CPPUNIT_ASSERT(!b.position.is_null());
        CPPUNIT_ASSERT(fsys::exists(fsys::path(b.directory) / position_estimator::weights_file));
        const auto& row = b.position.at("metrics").at("by_snr").at(0);
        CPPUNIT_ASSERT_EQUAL(30.0, row.at("snr_db").get<double>());
        CPPUNIT_ASSERT(row.contains("crb_azimuth_rad")); // the default scene: one unfaded path per frame
        const position_estimator p(b, 1);
        CPPUNIT_ASSERT_EQUAL(8, p.n_elements());
        for (double az : { -0.7, -0.2, 0.05, 0.6 }) {
            double truth_index = 0.0;
            const auto y = one_target(b, p.array(), az, &truth_index);
            const auto e = p.estimate(y.data(), 1).at(0);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(az, e.azimuth_rad, 2e-3);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(truth_index, e.delay_index, 0.5);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(b.frame.range_from_delay(e.delay_s), e.range_m, 1e-9);
        }
    }

    void bad_input_bundles_and_settings_are_refused_by_name()
    {
        const auto& r = shared_position_run();
        const position_estimator p(model_bundle::load(r.bundle.directory), 1);
        double ignored = 0.0;
        auto y = one_target(p.bundle(), p.array(), 0.1, &ignored);
        y[size_t(3 * p.n_pilots() + 5)] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
        assert_error([&] { p.estimate(y.data(), 1); }, "frame 0", "element 3, pilot 5");
        // A delay bundle without the record, and a record that does not fit.
        assert_error([] { position_estimator(model_bundle::load(qa::models_dir() + "delay_single"), 1); },
                     "bundle.json", "not a position bundle");
        const auto copy = qa::temp_dir("position", "edited");
        fsys::copy(r.bundle.directory, copy);
        qa::edit_json(copy + "/bundle.json", [](nlohmann::json& j) { j["position"]["angle"]["kernel"] = 4; });
        assert_error([&] { position_estimator(model_bundle::load(copy), 1); }, "position.angle", "kernel");
        fsys::remove_all(copy);
        const auto classifier = qa::temp_dir("position", "classifier");
        fsys::copy(qa::models_dir() + "classifier", classifier);
        qa::edit_json(classifier + "/bundle.json", [](nlohmann::json& j) { j["position"] = nlohmann::json::object(); });
        assert_error([&] { model_bundle::load(classifier); }, "position", "a delay bundle with an angle decoder");
        fsys::remove_all(classifier);
        // Settings.
        position_training_settings s;
        s.frames = 5;
        assert_error([&] { s.validate(); }, "frames", "at least 10");
        s = {};
        s.array = "mimo3x4_77g";
        s.delay_bundle = qa::models_dir() + "delay_single";
        assert_error([&] { train_position(s, nullptr); }, "array", "3 transmit elements");
        s = {};
        s.delay_bundle = qa::models_dir() + "classifier";
        assert_error([&] { train_position(s, nullptr); }, "delay_bundle", "not a delay bundle");
        s = {};
        s.delay_bundle = qa::models_dir() + "delay_single";
        s.angle.azimuth_max_rad = 0.5;
        s.frames = 40;
        assert_error([&] { train_position(s, nullptr); }, "angle", "outside the grid");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_position);
