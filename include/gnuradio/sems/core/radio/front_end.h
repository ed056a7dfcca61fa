// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The radio front end around the time-domain channel, in datasheet units, and its
 *        radio file ("format": "sems.radio"; docs/guides/radio_front_end.md).
 *
 * Reference powers. The channel's paths have mean powers summing to 1 (the echo's mean power
 * gain is 1, docs/design.md §1) and its noise has the power σ² = 10^(−SNR/10) per sample, the
 * SNR per resource element against unit-power transmitted samples. The leakage is stated
 * against that echo: L dB over the echo means a leakage path of power gain 10^(L/10), so with
 * any transmitted power P the leakage arrives with 10^(L/10)·P against the echo's mean P.
 */
#ifndef INCLUDED_SEMS_CORE_FRONT_END_H
#define INCLUDED_SEMS_CORE_FRONT_END_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Whether the transmitter and the receiver share one oscillator. */
enum class oscillator_kind {
    shared,  ///< monostatic: one oscillator up- and down-converts (no CFO, no SFO)
    separate ///< bistatic: two independent oscillators of the same phase noise, with CFO and SFO
};

/*! \brief The name in radio files. \param k the kind. \return "shared" or "separate". */
SEMS_API std::string oscillator_name(oscillator_kind k);
/*!
 * \brief The kind from its name. \param name "shared" or "separate".
 * \return the kind. \throws std::invalid_argument naming the value.
 */
SEMS_API oscillator_kind oscillator_from_name(const std::string& name);

/*! \brief Whether the receive elements of an array down-convert with one oscillator or each with its own. */
enum class element_oscillator_kind {
    shared, ///< the receiver's one oscillator distributed to every element (a phase-synchronised array)
    own     ///< each element its own oscillator of the same phase noise: element 0 the receiver's, the others independent
};

/*! \brief The name in radio files. \param k the kind. \return "shared" or "own". */
SEMS_API std::string element_oscillator_name(element_oscillator_kind k);
/*!
 * \brief The kind from its name. \param name "shared" or "own".
 * \return the kind. \throws std::invalid_argument naming the value.
 */
SEMS_API element_oscillator_kind element_oscillator_from_name(const std::string& name);

/*!
 * \brief The impairments of an SDR front end. The defaults are the ideal radio: every
 *        impairment off, so the front end passes the channel's output through unchanged.
 * \details Optional fields are off when empty. The defaults here are the project's only copy
 * (the radio file, the bindings and the GRC block take them from here).
 */
struct SEMS_API front_end_settings {
    /*!
     * \brief Transmitter-to-receiver leakage power in dB over the echo's mean power (the
     *        channel's unit mean power gain); empty = no leakage.
     */
    std::optional<double> leakage_db;
    /*! \brief Taps of the leakage path, at delays 0, 1, ... samples (1 to 64). */
    int leakage_taps = 3;
    /*! \brief Decay of the leakage taps' power: tap k has power ∝ exp(−k / decay), in samples (> 0). */
    double leakage_decay_samples = 1.0;

    /*!
     * \brief Phase noise L(f) in dBc/Hz at phase_noise_offset_hz (a free-running 1/f²
     *        oscillator, phase_noise.h); empty = clean oscillators. Must be below 0 dBc/Hz and
     *        on the 1/f² skirt (the Lorentzian corner D/(4π) below the offset).
     */
    std::optional<double> phase_noise_dbc_hz;
    /*! \brief The offset in Hz at which phase_noise_dbc_hz is quoted (> 0). */
    double phase_noise_offset_hz = 100e3;
    /*! \brief One oscillator for both ends (monostatic) or two (bistatic). */
    oscillator_kind oscillator = oscillator_kind::shared;
    /*!
     * \brief With several receive elements: every element down-converts with the receiver's
     *        oscillator (shared) or each with its own (own: independent phase noise of the same
     *        L(f), the same CFO and SFO, as receivers locked to one reference clock). Element 0
     *        keeps the receiver's oscillator either way. "own" needs phase noise.
     */
    element_oscillator_kind element_oscillators = element_oscillator_kind::shared;

    /*! \brief Receiver IQ gain imbalance in dB, I rail over Q rail (|x| ≤ 20 dB). */
    double iq_gain_db = 0.0;
    /*! \brief Receiver IQ phase imbalance in degrees (|x| < 90). */
    double iq_phase_deg = 0.0;

    /*!
     * \brief DC offset at the converter's input, in dB relative to the rms of the signal
     *        arriving there (dBc), equal on I and Q (phase 45°); empty = none.
     */
    std::optional<double> dc_offset_db;

    /*!
     * \brief The converter's effective number of bits (1 to 24); empty = an ideal converter
     *        (no quantization, no clipping).
     */
    std::optional<double> adc_enob;
    /*!
     * \brief Full scale of each converter rail (I and Q clip at ±full scale) as a multiple of
     *        that rail's rms, the complex rms of the arriving signal over √2 (> 0).
     */
    double adc_full_scale_rms = 4.0;

    /*! \brief Carrier frequency offset of the receiver's oscillator in Hz (separate oscillators only). */
    double cfo_hz = 0.0;
    /*! \brief Sample clock offset of the receiver's converter in ppm (separate oscillators only, |x| <= 1000). */
    double sfo_ppm = 0.0;

    /*!
     * \brief Refuses every value outside its physical range.
     * \throws std::invalid_argument naming the parameter and its value.
     */
    void validate() const;

    /*! \brief True when no impairment is on. \return whether the settings are the ideal radio. */
    bool is_ideal() const;
    /*!
     * \brief The phase diffusion of each oscillator (phase_diffusion_from_dbc).
     * \return D in rad²/s, 0 without phase noise.
     */
    double phase_diffusion() const;
    /*!
     * \brief The leakage path: leakage_taps real taps at delays 0, 1, ... samples, power
     *        ∝ exp(−k/decay), scaled so that Σ|h_k|² = 10^(leakage_db/10).
     * \return the taps (empty without leakage).
     */
    std::vector<gr_complex> leakage_response() const;
    /*!
     * \brief The receiver IQ imbalance as y = μ·x + ν·x*, in GNU Radio's convention
     *        (channels.iqbal_gen, receiver mode: I' = g(I cos φ + Q sin φ), Q' = Q, g = 10^(dB/20)).
     * \return μ = (1 + g e^{−jφ})/2.
     */
    std::complex<double> iq_mu() const;
    /*! \brief The image coefficient of iq_mu(). \return ν = (g e^{jφ} − 1)/2. */
    std::complex<double> iq_nu() const;

    /*!
     * \brief The DC offset's amplitude at the converter's input: 10^(dc_offset_db/20) times
     *        the complex rms of the signal arriving there (the IQ-imbalanced transmission,
     *        leakage and noise); it is added at phase 45° (equal on I and Q).
     * \param tx_power mean power of the transmitted samples (1 for unit resource elements on
     *        every subcarrier, (M − G)/M with G guards)
     * \param noise_variance the channel's noise power per sample (0 without noise)
     * \return |DC| in the channel's units, 0 without a DC offset.
     */
    double dc_amplitude(double tx_power, double noise_variance) const;
    /*!
     * \brief The complex rms the converter expects, DC included: the IQ-imbalanced
     *        (|μ|² + |ν|²)·(tx_power·(1 + leakage) + noise) plus |DC|².
     * \param tx_power as dc_amplitude() \param noise_variance as dc_amplitude()
     * \return the rms in the channel's units.
     */
    double expected_rms(double tx_power, double noise_variance) const;
    /*!
     * \brief Each converter rail's full scale: adc_full_scale_rms · expected_rms() / √2.
     * \param tx_power as dc_amplitude() \param noise_variance as dc_amplitude()
     * \return the full scale in the channel's units; 0 with an ideal converter (nothing clips).
     */
    double full_scale(double tx_power, double noise_variance) const;

    /*! \brief The radio file's JSON. \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads a radio from JSON (unknown keys refused).
     * \param j the JSON object \param source names the origin in errors
     * \return the validated settings.
     * \throws std::invalid_argument naming `source`, the field and the problem.
     */
    static front_end_settings from_json(const nlohmann::json& j, const std::string& source);
    /*!
     * \brief Parses radio JSON text. \param json_text the JSON \param source names the text in errors
     * \return the validated settings. \throws std::invalid_argument naming `source` and the field.
     */
    static front_end_settings parse(const std::string& json_text, const std::string& source = "radio text");
    /*!
     * \brief Reads a radio file. \param path the file
     * \return the validated settings. \throws std::invalid_argument naming the file and the field.
     */
    static front_end_settings load(const std::string& path);
    /*! \brief The radio file's text. \return the JSON text. */
    std::string to_json_string() const;
    /*! \brief Writes the radio file. \param path the file. \throws std::invalid_argument naming the file if it cannot be written. */
    void save(const std::string& path) const;

    /*! \brief Field-by-field equality. \param o the other settings. \return true if every field is equal. */
    bool operator==(const front_end_settings& o) const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_FRONT_END_H */
