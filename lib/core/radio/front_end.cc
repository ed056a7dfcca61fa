// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: front-end settings — validation, derived quantities and the radio file. */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/common/json_object.h"
#include <gnuradio/sems/core/radio/front_end.h>
#include <gnuradio/sems/core/radio/phase_noise.h>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {
constexpr const char* format_name = "sems.radio";
constexpr int format_version = 1;

using checks::text;

[[noreturn]] void refuse(const std::string& name, const std::string& rule, double v)
{
    throw std::invalid_argument("front end: " + name + " must be " + rule + ", got " + text(v));
}

void check_finite(const char* name, double v)
{
    if (!checks::finite(v))
        refuse(name, "finite", v);
}

void check_range(const char* name, double v, double lo, double hi, const std::string& rule)
{
    if (!checks::finite(v) || v < lo || v > hi)
        refuse(name, rule, v);
}
} // namespace

std::string oscillator_name(oscillator_kind k) { return k == oscillator_kind::shared ? "shared" : "separate"; }

oscillator_kind oscillator_from_name(const std::string& name)
{
    if (name == "shared")
        return oscillator_kind::shared;
    if (name == "separate")
        return oscillator_kind::separate;
    throw std::invalid_argument("front end: oscillator must be \"shared\" or \"separate\", got \"" + name + "\"");
}

std::string element_oscillator_name(element_oscillator_kind k)
{
    return k == element_oscillator_kind::shared ? "shared" : "own";
}

element_oscillator_kind element_oscillator_from_name(const std::string& name)
{
    if (name == "shared")
        return element_oscillator_kind::shared;
    if (name == "own")
        return element_oscillator_kind::own;
    throw std::invalid_argument("front end: element_oscillators must be \"shared\" or \"own\", got \"" + name + "\"");
}

void front_end_settings::validate() const
{
    if (leakage_db)
        check_finite("leakage_db", *leakage_db);
    if (leakage_taps < 1 || leakage_taps > 64)
        refuse("leakage_taps", "in [1, 64]", leakage_taps);
    if (!checks::positive(leakage_decay_samples))
        refuse("leakage_decay_samples", "positive and finite", leakage_decay_samples);
    if (!checks::positive(phase_noise_offset_hz))
        refuse("phase_noise_offset_hz", "positive and finite", phase_noise_offset_hz);
    if (phase_noise_dbc_hz) {
        const double l = *phase_noise_dbc_hz;
        if (!checks::finite(l) || l >= 0.0)
            refuse("phase_noise_dbc_hz", "finite and below 0 dBc/Hz", l);
        // On the 1/f² skirt: the Lorentzian's corner D/(4π) = π f² 10^(L/10) below f.
        if (pi * phase_noise_offset_hz * std::pow(10.0, l / 10.0) >= 1.0)
            refuse("phase_noise_dbc_hz",
                   "below 10·log10(1/(π·offset)) = " + text(-10.0 * std::log10(pi * phase_noise_offset_hz)) +
                       " dBc/Hz at the offset of " + text(phase_noise_offset_hz) +
                       " Hz (else the offset lies inside the oscillator's Lorentzian corner, not on its 1/f² skirt)",
                   l);
    }
    check_range("iq_gain_db", iq_gain_db, -20.0, 20.0, "in [-20, 20] dB");
    if (!checks::finite(iq_phase_deg) || std::fabs(iq_phase_deg) >= 90.0)
        refuse("iq_phase_deg", "in (-90, 90) degrees", iq_phase_deg);
    if (dc_offset_db)
        check_finite("dc_offset_db", *dc_offset_db);
    if (adc_enob)
        check_range("adc_enob", *adc_enob, 1.0, 24.0, "in [1, 24] bits");
    if (!checks::positive(adc_full_scale_rms))
        refuse("adc_full_scale_rms", "positive and finite", adc_full_scale_rms);
    check_finite("cfo_hz", cfo_hz);
    check_range("sfo_ppm", sfo_ppm, -1000.0, 1000.0, "in [-1000, 1000] ppm");
    if (element_oscillators == element_oscillator_kind::own && !phase_noise_dbc_hz)
        throw std::invalid_argument("front end: element_oscillators \"own\" needs phase noise (phase_noise.dbc_hz): "
                                    "without it every element's oscillator is the same clean one");
    if (oscillator == oscillator_kind::shared) {
        if (cfo_hz != 0.0)
            refuse("cfo_hz", "0 with a shared oscillator (set oscillator to separate)", cfo_hz);
        if (sfo_ppm != 0.0)
            refuse("sfo_ppm", "0 with a shared oscillator (set oscillator to separate)", sfo_ppm);
    }
}

bool front_end_settings::is_ideal() const
{
    return !leakage_db && !phase_noise_dbc_hz && iq_gain_db == 0.0 && iq_phase_deg == 0.0 && !dc_offset_db &&
           !adc_enob && cfo_hz == 0.0 && sfo_ppm == 0.0;
}

double front_end_settings::phase_diffusion() const
{
    return phase_noise_dbc_hz ? phase_diffusion_from_dbc(*phase_noise_dbc_hz, phase_noise_offset_hz) : 0.0;
}

std::vector<gr_complex> front_end_settings::leakage_response() const
{
    if (!leakage_db)
        return {};
    std::vector<double> p(static_cast<size_t>(leakage_taps));
    double sum = 0.0;
    for (int k = 0; k < leakage_taps; ++k)
        sum += p[k] = std::exp(-k / leakage_decay_samples);
    const double total = std::pow(10.0, *leakage_db / 10.0);
    std::vector<gr_complex> h;
    h.reserve(p.size());
    for (double pk : p)
        h.emplace_back(static_cast<float>(std::sqrt(total * pk / sum)), 0.0f);
    return h;
}

std::complex<double> front_end_settings::iq_mu() const
{
    const double g = std::pow(10.0, iq_gain_db / 20.0);
    return 0.5 * (1.0 + g * std::polar(1.0, -iq_phase_deg * pi / 180.0));
}

std::complex<double> front_end_settings::iq_nu() const
{
    const double g = std::pow(10.0, iq_gain_db / 20.0);
    return 0.5 * (g * std::polar(1.0, iq_phase_deg * pi / 180.0) - 1.0);
}

namespace {
// The mean power arriving at the converter without the DC: the IQ-imbalanced transmission
// (echo and leakage) and noise.
double arriving_power(const front_end_settings& s, double tx_power, double noise_variance)
{
    const double leak = s.leakage_db ? std::pow(10.0, *s.leakage_db / 10.0) : 0.0;
    return (std::norm(s.iq_mu()) + std::norm(s.iq_nu())) * (tx_power * (1.0 + leak) + noise_variance);
}
} // namespace

double front_end_settings::dc_amplitude(double tx_power, double noise_variance) const
{
    return dc_offset_db ? std::pow(10.0, *dc_offset_db / 20.0) * std::sqrt(arriving_power(*this, tx_power, noise_variance))
                        : 0.0;
}

double front_end_settings::expected_rms(double tx_power, double noise_variance) const
{
    const double dc = dc_amplitude(tx_power, noise_variance);
    return std::sqrt(arriving_power(*this, tx_power, noise_variance) + dc * dc);
}

double front_end_settings::full_scale(double tx_power, double noise_variance) const
{
    return adc_enob ? adc_full_scale_rms * expected_rms(tx_power, noise_variance) / std::sqrt(2.0) : 0.0;
}

nlohmann::json front_end_settings::to_json() const
{
    nlohmann::json j = { { "format", format_name }, { "version", format_version } };
    if (leakage_db)
        j["leakage"] = { { "power_over_echo_db", *leakage_db },
                         { "taps", leakage_taps },
                         { "decay_samples", leakage_decay_samples } };
    if (phase_noise_dbc_hz)
        j["phase_noise"] = { { "dbc_hz", *phase_noise_dbc_hz }, { "offset_hz", phase_noise_offset_hz } };
    j["oscillator"] = oscillator_name(oscillator);
    if (element_oscillators != element_oscillator_kind::shared) // absent: shared (radio files before arrays)
        j["element_oscillators"] = element_oscillator_name(element_oscillators);
    j["iq_imbalance"] = { { "gain_db", iq_gain_db }, { "phase_deg", iq_phase_deg } };
    if (dc_offset_db)
        j["dc_offset_db"] = *dc_offset_db;
    if (adc_enob)
        j["converter"] = { { "enob", *adc_enob }, { "full_scale_over_rms", adc_full_scale_rms } };
    j["cfo_hz"] = cfo_hz;
    j["sfo_ppm"] = sfo_ppm;
    return j;
}

front_end_settings front_end_settings::from_json(const nlohmann::json& j, const std::string& source)
{
    using namespace json_read;
    object_reader top = file_object(j, format_name, format_version, source);
    front_end_settings s;
    if (top.has("leakage")) {
        object_reader r = top.object("leakage");
        s.leakage_db = r.number("power_over_echo_db");
        s.leakage_taps = r.int_or("taps", s.leakage_taps, 1, 64);
        s.leakage_decay_samples = r.number_or("decay_samples", s.leakage_decay_samples);
        r.finish();
    }
    if (top.has("phase_noise")) {
        object_reader r = top.object("phase_noise");
        s.phase_noise_dbc_hz = r.number("dbc_hz");
        s.phase_noise_offset_hz = r.number_or("offset_hz", s.phase_noise_offset_hz);
        r.finish();
    }
    if (top.has("oscillator")) {
        try {
            s.oscillator = oscillator_from_name(top.string("oscillator"));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(source + ": " + e.what());
        }
    }
    if (top.has("element_oscillators")) {
        try {
            s.element_oscillators = element_oscillator_from_name(top.string("element_oscillators"));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(source + ": " + e.what());
        }
    }
    if (top.has("iq_imbalance")) {
        object_reader r = top.object("iq_imbalance");
        s.iq_gain_db = r.number_or("gain_db", s.iq_gain_db);
        s.iq_phase_deg = r.number_or("phase_deg", s.iq_phase_deg);
        r.finish();
    }
    if (top.has("dc_offset_db"))
        s.dc_offset_db = top.number("dc_offset_db");
    if (top.has("converter")) {
        object_reader r = top.object("converter");
        s.adc_enob = r.number("enob");
        s.adc_full_scale_rms = r.number_or("full_scale_over_rms", s.adc_full_scale_rms);
        r.finish();
    }
    s.cfo_hz = top.number_or("cfo_hz", s.cfo_hz);
    s.sfo_ppm = top.number_or("sfo_ppm", s.sfo_ppm);
    top.finish();
    try {
        s.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(source + ": " + e.what());
    }
    return s;
}

front_end_settings front_end_settings::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

front_end_settings front_end_settings::load(const std::string& path)
{
    return from_json(json_read::parse_file(path), path);
}

std::string front_end_settings::to_json_string() const { return to_json().dump(2); }

void front_end_settings::save(const std::string& path) const { json_read::write_file(path, to_json()); }

bool front_end_settings::operator==(const front_end_settings& o) const
{
    return leakage_db == o.leakage_db && leakage_taps == o.leakage_taps &&
           leakage_decay_samples == o.leakage_decay_samples && phase_noise_dbc_hz == o.phase_noise_dbc_hz &&
           phase_noise_offset_hz == o.phase_noise_offset_hz && oscillator == o.oscillator &&
           element_oscillators == o.element_oscillators &&
           iq_gain_db == o.iq_gain_db && iq_phase_deg == o.iq_phase_deg && dc_offset_db == o.dc_offset_db &&
           adc_enob == o.adc_enob && adc_full_scale_rms == o.adc_full_scale_rms && cfo_hz == o.cfo_hz &&
           sfo_ppm == o.sfo_ppm;
}

} // namespace sems
} // namespace gr
