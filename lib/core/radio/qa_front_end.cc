// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the radio front end's settings (validation, radio files, derived quantities) and
 * the oscillator's Wiener phase against its closed forms. */
#include <gnuradio/sems/core/radio/front_end.h>
#include <gnuradio/sems/core/radio/phase_noise.h>
#include "core/common/math_constants.h"
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
const double inf = std::numeric_limits<double>::infinity();
const double not_a_number = std::numeric_limits<double>::quiet_NaN();

// Refused by validate() with a message naming `name` and containing `value`.
void refused(const std::function<void(front_end_settings&)>& change, const std::string& name, const std::string& value)
{
    front_end_settings s;
    change(s);
    assert_error([&] { s.validate(); }, name, value);
}

std::string source_dir()
{
    const char* src = std::getenv("SEMS_SOURCE_DIR");
    CPPUNIT_ASSERT_MESSAGE("SEMS_SOURCE_DIR must point at the source tree", src != nullptr);
    return src;
}
} // namespace

class qa_front_end : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_front_end);
    CPPUNIT_TEST(defaults_are_ideal);
    CPPUNIT_TEST(validate_names_every_parameter);
    CPPUNIT_TEST(radio_file_round_trips);
    CPPUNIT_TEST(radio_file_errors_name_file_and_key);
    CPPUNIT_TEST(shipped_radios);
    CPPUNIT_TEST(leakage_response_power_and_decay);
    CPPUNIT_TEST(iq_coefficients_match_gnuradio_model);
    CPPUNIT_TEST(diffusion_from_datasheet_point);
    CPPUNIT_TEST(wiener_increments_have_variance_k_d_over_fs);
    CPPUNIT_TEST(phase_is_seeded_and_call_size_free);
    CPPUNIT_TEST_SUITE_END();

public:
    void defaults_are_ideal()
    {
        front_end_settings s;
        s.validate();
        CPPUNIT_ASSERT(s.is_ideal());
        CPPUNIT_ASSERT(s.leakage_response().empty());
        CPPUNIT_ASSERT_EQUAL(0.0, s.phase_diffusion());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(s.iq_mu()), 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(s.iq_nu()), 1e-15);
        s.adc_enob = 12;
        CPPUNIT_ASSERT(!s.is_ideal());
    }

    void validate_names_every_parameter()
    {
        refused([](auto& s) { s.leakage_db = inf; }, "leakage_db", "inf");
        refused([](auto& s) { s.leakage_db = not_a_number; }, "leakage_db", "nan");
        refused([](auto& s) { s.leakage_taps = 0; }, "leakage_taps", "0");
        refused([](auto& s) { s.leakage_taps = 65; }, "leakage_taps", "65");
        refused([](auto& s) { s.leakage_decay_samples = 0; }, "leakage_decay_samples", "0");
        refused([](auto& s) { s.leakage_decay_samples = -1; }, "leakage_decay_samples", "-1");
        refused([](auto& s) { s.phase_noise_dbc_hz = 3.0; }, "phase_noise_dbc_hz", "3");
        refused([](auto& s) { s.phase_noise_dbc_hz = 0.0; }, "phase_noise_dbc_hz", "0");
        refused([](auto& s) { s.phase_noise_dbc_hz = -inf; }, "phase_noise_dbc_hz", "inf");
        // -50 dBc/Hz at 100 kHz: the Lorentzian corner (π·f·L = 3.1 MHz) lies above the offset.
        refused([](auto& s) { s.phase_noise_dbc_hz = -50.0; }, "phase_noise_dbc_hz", "1/f");
        refused([](auto& s) { s.phase_noise_offset_hz = -100e3; }, "phase_noise_offset_hz", "-100000");
        refused([](auto& s) { s.phase_noise_offset_hz = 0; }, "phase_noise_offset_hz", "0");
        refused([](auto& s) { s.iq_gain_db = not_a_number; }, "iq_gain_db", "nan");
        refused([](auto& s) { s.iq_gain_db = 25; }, "iq_gain_db", "25");
        refused([](auto& s) { s.iq_phase_deg = 90; }, "iq_phase_deg", "90");
        refused([](auto& s) { s.iq_phase_deg = -inf; }, "iq_phase_deg", "inf");
        refused([](auto& s) { s.dc_offset_db = inf; }, "dc_offset_db", "inf");
        refused([](auto& s) { s.adc_enob = -2.0; }, "adc_enob", "-2");
        refused([](auto& s) { s.adc_enob = 0.0; }, "adc_enob", "0");
        refused([](auto& s) { s.adc_enob = 40.0; }, "adc_enob", "40");
        refused([](auto& s) { s.adc_enob = not_a_number; }, "adc_enob", "nan");
        refused([](auto& s) { s.adc_full_scale_rms = 0.0; }, "adc_full_scale_rms", "0");
        refused([](auto& s) { s.adc_full_scale_rms = -4.0; }, "adc_full_scale_rms", "-4");
        refused([](auto& s) { s.adc_full_scale_rms = inf; }, "adc_full_scale_rms", "inf");
        refused([](auto& s) { s.oscillator = oscillator_kind::separate; s.cfo_hz = not_a_number; }, "cfo_hz", "nan");
        refused([](auto& s) { s.oscillator = oscillator_kind::separate; s.sfo_ppm = 2000; }, "sfo_ppm", "2000");
        // A shared oscillator has no frequency or clock offset.
        refused([](auto& s) { s.cfo_hz = 100; }, "cfo_hz", "shared");
        refused([](auto& s) { s.sfo_ppm = 1; }, "sfo_ppm", "shared");
        assert_error([] { oscillator_from_name("common"); }, "oscillator", "common");
        // An array's own oscillators need phase noise (else they are all the same clean one).
        assert_error([] {
            front_end_settings s;
            s.element_oscillators = element_oscillator_kind::own;
            s.validate();
        }, "element_oscillators", "phase noise");
        assert_error([] { element_oscillator_from_name("each"); }, "element_oscillators", "each");
    }

    void radio_file_round_trips()
    {
        front_end_settings s;
        s.leakage_db = 37.5;
        s.leakage_taps = 5;
        s.leakage_decay_samples = 0.7;
        s.phase_noise_dbc_hz = -95.25;
        s.phase_noise_offset_hz = 10e3;
        s.oscillator = oscillator_kind::separate;
        s.iq_gain_db = -0.3;
        s.iq_phase_deg = 1.7;
        s.dc_offset_db = -41.0;
        s.adc_enob = 10.5;
        s.adc_full_scale_rms = 3.3;
        s.cfo_hz = -1234.5;
        s.sfo_ppm = 2.5;
        s.element_oscillators = element_oscillator_kind::own;
        s.validate();
        const std::string path = "qa_front_end_round_trip.json";
        s.save(path);
        CPPUNIT_ASSERT(front_end_settings::load(path) == s);
        std::remove(path.c_str());
        CPPUNIT_ASSERT(front_end_settings::parse(s.to_json_string()) == s);
        // The ideal radio writes no optional group and reads back ideal.
        const front_end_settings ideal;
        const auto j = ideal.to_json();
        CPPUNIT_ASSERT(!j.contains("leakage") && !j.contains("phase_noise") && !j.contains("converter") &&
                       !j.contains("element_oscillators"));
        CPPUNIT_ASSERT(s.to_json().at("element_oscillators") == "own");
        CPPUNIT_ASSERT(front_end_settings::parse(ideal.to_json_string()).is_ideal());
    }

    void radio_file_errors_name_file_and_key()
    {
        const std::string head = R"({"format": "sems.radio", "version": 1, )";
        assert_error([&] { front_end_settings::parse(head + R"("leakge": {}})", "my.json"); }, "my.json", "leakge: unknown key");
        assert_error([&] { front_end_settings::parse(head + R"("converter": {"enob": 12, "bits": 3}})", "my.json"); },
                     "my.json", "converter.bits: unknown key");
        assert_error([&] { front_end_settings::parse(head + R"("converter": {"full_scale_over_rms": 3}})", "my.json"); },
                     "converter.enob", "missing");
        assert_error([&] { front_end_settings::parse(head + R"("phase_noise": {"dbc_hz": 10}})", "my.json"); },
                     "my.json", "phase_noise_dbc_hz");
        assert_error([&] { front_end_settings::parse(head + R"("oscillator": "both"})", "my.json"); }, "my.json", "both");
        assert_error([&] { front_end_settings::parse(head + R"("element_oscillators": "each"})", "my.json"); }, "my.json",
                     "each");
        assert_error([&] { front_end_settings::parse(head + R"("element_oscillators": "own"})", "my.json"); }, "my.json",
                     "needs phase noise");
        assert_error([&] { front_end_settings::parse(R"({"format": "sems.scene", "version": 1})", "my.json"); },
                     "my.json", "format");
        assert_error([&] { front_end_settings::parse(R"({"format": "sems.radio", "version": 2})", "my.json"); },
                     "my.json", "version");
        assert_error([&] { front_end_settings::load("no/such/radio.json"); }, "no/such/radio.json", "cannot open");
    }

    void shipped_radios()
    {
        const std::string dir = source_dir() + "/examples/radios/";
        CPPUNIT_ASSERT(front_end_settings::load(dir + "ideal.json").is_ideal());
        const auto m = front_end_settings::load(dir + "sdr_monostatic.json");
        CPPUNIT_ASSERT(m.leakage_db && *m.leakage_db == 40.0);
        CPPUNIT_ASSERT(m.phase_noise_dbc_hz && *m.phase_noise_dbc_hz == -90.0);
        CPPUNIT_ASSERT_EQUAL(100e3, m.phase_noise_offset_hz);
        CPPUNIT_ASSERT(m.oscillator == oscillator_kind::shared);
        CPPUNIT_ASSERT_EQUAL(0.5, m.iq_gain_db);
        CPPUNIT_ASSERT_EQUAL(3.0, m.iq_phase_deg);
        CPPUNIT_ASSERT(m.adc_enob && *m.adc_enob == 12.0);
        CPPUNIT_ASSERT_EQUAL(4.0, m.adc_full_scale_rms);
        const auto b = front_end_settings::load(dir + "sdr_bistatic.json");
        CPPUNIT_ASSERT(b.oscillator == oscillator_kind::separate);
        CPPUNIT_ASSERT(b.cfo_hz != 0.0 && b.sfo_ppm != 0.0);
    }

    void leakage_response_power_and_decay()
    {
        front_end_settings s;
        s.leakage_db = 40.0;
        s.leakage_taps = 4;
        s.leakage_decay_samples = 2.0;
        const auto h = s.leakage_response();
        CPPUNIT_ASSERT_EQUAL(size_t(4), h.size());
        double total = 0.0;
        for (const auto& t : h)
            total += std::norm(std::complex<double>(t));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1e4, total, 1e4 * 1e-6);
        for (size_t k = 1; k < h.size(); ++k) // power ratio e^{-1/decay} between taps
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::exp(-0.5), std::norm(h[k]) / std::norm(h[k - 1]), 1e-6);
    }

    void iq_coefficients_match_gnuradio_model()
    {
        front_end_settings s;
        s.iq_gain_db = 0.5;
        s.iq_phase_deg = 3.0;
        const double g = std::pow(10.0, 0.5 / 20.0), p = 3.0 * pi / 180.0;
        for (const std::complex<double> x : { std::complex<double>(0.3, -1.1), std::complex<double>(-2.0, 0.7) }) {
            // channels.iqbal_gen, receiver mode: I' = g (I cos p + Q sin p), Q' = Q.
            const std::complex<double> want(g * (x.real() * std::cos(p) + x.imag() * std::sin(p)), x.imag());
            const auto got = s.iq_mu() * x + s.iq_nu() * std::conj(x);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(got - want), 1e-12);
        }
    }

    void diffusion_from_datasheet_point()
    {
        // -90 dBc/Hz at 100 kHz: D = 4π²·1e10·1e-9 = 394.78 rad²/s.
        const double d = phase_diffusion_from_dbc(-90.0, 100e3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(4.0 * pi * pi * 10.0, d, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-90.0, phase_noise_dbc(d, 100e3), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-70.0, phase_noise_dbc(d, 10e3), 1e-12); // 1/f²: 20 dB per decade
        assert_error([] { phase_diffusion_from_dbc(-90.0, -1.0); }, "offset_hz", "-1");
        assert_error([] { phase_noise_process(-1.0, 30e6); }, "diffusion_rad2_per_s", "-1");
        assert_error([] { phase_noise_process(1.0, 0.0); }, "sample_rate_hz", "0");
    }

    void wiener_increments_have_variance_k_d_over_fs()
    {
        // φ[n] − φ[n−k] ~ N(0, k·D/fs): the phase error of a path k samples long under a shared
        // oscillator. Non-overlapping windows are independent: 20000 of them per lag, so the
        // sample variance is within 3·sqrt(2/20000) = 3% of the closed form.
        const double fs = 30e6, d = phase_diffusion_from_dbc(-90.0, 100e3);
        phase_noise_process p(d, fs, 7);
        CPPUNIT_ASSERT_EQUAL(0.0, p.next()); // φ[0] = 0
        for (int k : { 1, 10, 100 }) {
            const int windows = 20000;
            double sum2 = 0.0;
            double prev = p.next();
            for (int w = 0; w < windows; ++w) {
                double cur = prev;
                for (int i = 0; i < k; ++i)
                    cur = p.next();
                sum2 += (cur - prev) * (cur - prev);
                prev = cur;
            }
            const double want = k * d / fs;
            CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE("lag " + std::to_string(k), want, sum2 / windows, 0.03 * want);
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(d / fs, p.increment_variance(), 1e-18);
        // A clean oscillator stays at phase 0 (the zero-delay path of a shared one sees nothing).
        phase_noise_process clean(0.0, fs, 7);
        for (int i = 0; i < 1000; ++i)
            CPPUNIT_ASSERT_EQUAL(0.0, clean.next());
    }

    void phase_is_seeded_and_call_size_free()
    {
        const double d = 400.0, fs = 1e6;
        phase_noise_process a(d, fs, 3), b(d, fs, 3), c(d, fs, 4);
        std::vector<gr_complex> ya(1000), yb(1000), yc(1000);
        a.generate(ya.data(), 1000);
        b.generate(yb.data(), 1);
        b.generate(yb.data() + 1, 599);
        b.generate(yb.data() + 600, 400);
        c.generate(yc.data(), 1000);
        CPPUNIT_ASSERT(ya == yb);
        CPPUNIT_ASSERT(ya != yc);
        CPPUNIT_ASSERT_EQUAL(uint64_t(1000), a.samples());
        for (const auto& z : ya)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(z), 1e-6);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_front_end);
