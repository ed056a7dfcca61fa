# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: the time-domain target channel inside an SDR front end (docs/guides/radio_front_end.md)."""
import cmath
import json
import math
import sys

from gnuradio import analog, blocks, channels, filter, gr

from .core_python import frame_settings as _frame_settings
from .core_python import channel_model, front_end_settings, oscillator_from_name, oscillator_kind
from .core_python import element_oscillator_from_name, element_oscillator_kind
from .core_python import phase_noise_source, target_channel_td

_FRAME = _frame_settings()  # the frame defaults' one place (include/gnuradio/sems/core/frame/frame_settings.h)
_IDEAL = front_end_settings()  # the defaults' one place (include/gnuradio/sems/core/radio/front_end.h)
_SETTINGS = tuple(k for k in dir(_IDEAL) if not k.startswith("_") and not callable(getattr(_IDEAL, k)))
# Seeds of the oscillators, apart from the channel's own draws of the same seed (receive element
# k > 0 with its own oscillator: the receiver's seed plus k times _ELEMENT_OSC).
_TX_OSC, _RX_OSC, _ELEMENT_OSC = 0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9, 0x94D049BB133111EB
_MMSE_CENTRE = 3  # filter.mmse_resampler_cc: output 0 is input 3 (qa_radio_front_end checks it)


def radio_settings(radio="", **overrides):
    """The front end's settings: a radio file path, radio JSON text, "" (the ideal radio) or a
    front_end_settings (copied), then any field of front_end_settings given by keyword
    (leakage_db=40, adc_enob=12, oscillator="separate", ...). Validated: a bad value raises
    ValueError naming the parameter and the value, an unknown setting TypeError naming it."""
    if isinstance(radio, front_end_settings):
        s = front_end_settings.parse(radio.to_json_string())
    elif not radio:
        s = front_end_settings()
    elif radio.lstrip().startswith("{"):
        s = front_end_settings.parse(radio)
    else:
        s = front_end_settings.load(radio)
    for key, value in overrides.items():
        if key not in _SETTINGS:
            raise TypeError(f"radio_front_end: unknown setting {key!r} (known: {', '.join(sorted(_SETTINGS))})")
        if key == "oscillator" and isinstance(value, str):
            value = oscillator_from_name(value)
        if key == "element_oscillators" and isinstance(value, str):
            value = element_oscillator_from_name(value)
        setattr(s, key, value)
    s.validate()
    return s


def _check_tx_power(tx_power):
    if not (math.isfinite(tx_power) and tx_power > 0):
        raise ValueError(f"radio_front_end: tx_power must be positive and finite, got {tx_power}")


def _noise_variance(snr_db):
    """The channel's noise power per sample at an SNR per resource element (inf: none):
    channel_model.noise_variance, with a NaN named as this block's parameter."""
    if math.isnan(snr_db):
        raise ValueError("radio_front_end: snr_db is NaN")
    return channel_model.noise_variance(snr_db)


def _expected_rms(s, snr_db, tx_power):
    """(rms, dc) at the converter for settings s: the complex rms (DC included) and the DC's
    magnitude, from the core's one formula (front_end_settings.expected_rms, dc_amplitude)."""
    noise = _noise_variance(snr_db)
    return s.expected_rms(tx_power, noise), s.dc_amplitude(tx_power, noise)


def converter_full_scale(radio="", snr_db=float("inf"), tx_power=1.0, **settings):
    """Each rail's full scale of the radio's converter, in the channel's units, without building
    a flowgraph: what SemS Leakage Canceller takes as clip_level.

    radio, **settings: as radio_settings (a radio file path, radio JSON text, "" for the ideal
    radio, or a front_end_settings; keyword fields override it); snr_db: the channel's SNR per
    resource element in dB (inf: no noise); tx_power: the transmitted samples' mean power, as
    radio_front_end's.

    Returns adc_full_scale_rms * rms / sqrt(2), rms being the complex rms the converter expects
    (tx_power * (1 + leakage) + noise after the IQ imbalance, plus the DC): the level at which
    radio_front_end with the same arguments clips each rail (its full_scale()). An ideal
    converter (adc_enob None) quantizes and clips nothing, so it has no full scale: 0.0, the
    canceller's "no clipping handled". A bad value or tx_power: ValueError naming it; an unknown
    setting: TypeError.
    """
    s = radio_settings(radio, **settings)
    _check_tx_power(tx_power)
    return s.full_scale(tx_power, _noise_variance(snr_db))


RECORDING_INFO_FORMAT = "sems.radio_recording"  # <recording>.json: what the radio was


def write_recording_info(recording, radio="", snr_db=float("inf"), tx_power=1.0, **settings):
    """Writes <recording>.json next to a raw recording made through radio_front_end: the radio's
    settings, snr_db (null for inf), tx_power and the converter's full scale per rail
    (converter_full_scale of the same arguments; 0.0 for an ideal converter), so that a replay
    gives the leakage canceller the right clip_level. Returns the full scale written.

        {"format": "sems.radio_recording", "version": 1, "converter_full_scale": <per rail>,
         "snr_db": 20, "tx_power": 1.0, "radio": {<the radio file's object, overrides applied>}}
    """
    s = radio_settings(radio, **settings)
    full_scale = converter_full_scale(s, snr_db, tx_power)
    info = {"format": RECORDING_INFO_FORMAT, "version": 1, "converter_full_scale": full_scale,
            "snr_db": None if math.isinf(snr_db) else snr_db, "tx_power": tx_power,
            "radio": json.loads(s.to_json_string())}
    path = recording + ".json"
    try:
        with open(path, "w") as f:
            json.dump(info, f, indent=1)
            f.write("\n")
    except OSError as e:
        raise ValueError(f"write_recording_info: cannot write {path}: {e}") from None
    return full_scale


def recorded_full_scale(recording):
    """The converter's full scale per rail recorded in <recording>.json (write_recording_info),
    for the leakage canceller's clip_level. A recording without that file (made before the
    full scale was recorded, or by another tool) gives 0.0, no clipping handled, and a note on
    stderr saying so; a file that is not such a record, or whose full scale is not a finite
    number >= 0, raises ValueError naming the file and the key."""
    path = recording + ".json"
    try:
        with open(path) as f:
            text = f.read()
    except FileNotFoundError:
        print(f"sems: {path} not found: the recording does not say the converter's full scale; "
              "clip_level 0 (the leakage canceller handles no clipping)", file=sys.stderr, flush=True)
        return 0.0
    except OSError as e:
        raise ValueError(f"recorded_full_scale: cannot read {path}: {e}") from None
    try:
        info = json.loads(text)
    except ValueError as e:
        raise ValueError(f"{path}: not JSON: {e}") from None
    if not isinstance(info, dict) or info.get("format") != RECORDING_INFO_FORMAT:
        raise ValueError(f"{path}: format: expected {RECORDING_INFO_FORMAT!r}")
    if info.get("version") != 1:
        raise ValueError(f"{path}: version: expected 1, got {info.get('version')!r}")
    value = info.get("converter_full_scale")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{path}: converter_full_scale: must be a finite number >= 0, got {value!r}")
    return float(value)


class radio_front_end(gr.hier_block2):
    """The time-domain target channel (target_channel_td) inside an SDR front end: the
    transmitted samples in, what the receiver's converter delivers out.

    Complex samples in (what ofdm_tx emits), complex samples out, sample-aligned 1:1; with an
    array in the scene (n_receive > 1), one output per receive element, each through its own
    receiver chain below:

        x -> [x TX oscillator] -> target_channel_td (echo + noise) -+-> [x conj RX oscillator]
                              \\-> leakage FIR --------------------/
          -> [CFO rotator] -> RX IQ imbalance (channels.iqbal_gen) -> + DC -> [SFO resampler] -> converter

    The oscillators are sems.phase_noise_source streams: one (shared, monostatic) multiplies
    the transmitted samples and, conjugated, the received ones, so the echo at delay tau sees
    phi(t - tau) - phi(t); two with independent seeds when separate (bistatic). Receive
    elements down-convert with the receiver's oscillator (element_oscillators "shared", a
    phase-synchronised array) or element k > 0 with its own of the same phase noise ("own");
    CFO, SFO, IQ imbalance, DC and converter settings are every element's. The leakage
    path (front_end_settings.leakage_response, causal, first tap at delay 0) is added to the
    echo; the echo itself goes through nothing but the channel, so the chain stays sample-
    aligned 1:1. The converter scales so that each rail's full scale is adc_full_scale_rms
    times its expected rms, clips at full scale (analog.rail_ff), quantizes to adc_enob bits
    (blocks.float_to_int and int_to_float, rounding to steps of 2^(1 - ENOB) full scale; up to
    24 bits) and scales back: the
    output is in the channel's units. A sample clock offset (separate oscillators) resamples
    with filter.mmse_resampler_cc (8-tap MMSE interpolator, aligned so that output k is the
    input at k / (1 + sfo)): the stream then drifts against the frames by sfo samples per
    sample, as a real receiver's does, and the interpolator is accurate for signals well inside
    the band (its error grows towards the band edges). The expected rms is that of
    tx_power * (1 + leakage) + noise after the IQ imbalance, plus the DC.

    With the ideal settings (every impairment off) the block is target_channel_td alone.

    radio: radio file path, radio JSON text or "" (ideal; then keyword settings apply);
    **settings: fields of front_end_settings overriding the file's; tx_power: mean power of
    the transmitted samples (1 for unit-power resource elements on every subcarrier, (M - G)/M
    with G guard subcarriers);
    n_receive: the scene's receive elements (1 without an array; a mismatch is refused naming
    both counts); the other arguments are target_channel_td's (one transmit element).
    """

    def __init__(self, radio="", scene="", classes=(), n_targets=1, paths_per_target=1,
                 micro_doppler=True, clutter_paths=0, clutter_csr_db=0.0,
                 snr_db=float("inf"), seed=0,
                 n_symbols=_FRAME.n_symbols, n_subcarriers=_FRAME.n_subcarriers,
                 bandwidth_hz=_FRAME.bandwidth_hz, carrier_hz=_FRAME.carrier_hz,
                 symbol_interval_s=_FRAME.symbol_interval_s, cp_len=_FRAME.cp_len,
                 class_library="paper", tx_power=1.0, n_receive=1, **settings):
        gr.hier_block2.__init__(
            self, "sems_radio_front_end",
            gr.io_signature(1, 1, gr.sizeof_gr_complex),
            gr.io_signature(n_receive, n_receive, gr.sizeof_gr_complex))
        self.settings = radio_settings(radio, **settings)
        s = self.settings
        _check_tx_power(tx_power)
        self.tx_power = tx_power
        self.channel = target_channel_td(scene, list(classes), n_targets, paths_per_target, micro_doppler,
                                         clutter_paths, clutter_csr_db, snr_db, seed, n_symbols,
                                         n_subcarriers, bandwidth_hz, carrier_hz, symbol_interval_s,
                                         cp_len, class_library, n_receive, 1)
        self.n_receive = n_receive
        fs = bandwidth_hz
        mask = (1 << 64) - 1
        #: The seeds of the TX and RX oscillators (phase_noise_process regenerates their phases).
        self.oscillator_seeds = ((seed + _TX_OSC) & mask, (seed + _RX_OSC) & mask)
        #: Each receive element's oscillator seed: the receiver's (the TX's when shared), and with
        #: element_oscillators "own" element k's own beyond element 0.
        own = s.element_oscillators == element_oscillator_kind.own
        rx_seed = self.oscillator_seeds[1 if s.oscillator == oscillator_kind.separate else 0]
        self.element_oscillator_seeds = [(rx_seed + (k * _ELEMENT_OSC if own else 0)) & mask for k in range(n_receive)]

        # Transmitter: up-conversion by the TX oscillator.
        tx = (self, 0)
        self.tx_osc = self.rx_osc = None
        if s.phase_noise_dbc_hz is not None:
            self.tx_osc = phase_noise_source(fs, s.phase_noise_dbc_hz, s.phase_noise_offset_hz,
                                             self.oscillator_seeds[0])
            self.tx_mix = blocks.multiply_cc()
            self.connect(tx, (self.tx_mix, 0))
            self.connect(self.tx_osc, (self.tx_mix, 1))
            tx = (self.tx_mix, 0)
            self.rx_osc = self.tx_osc
            if s.oscillator == oscillator_kind.separate:
                self.rx_osc = phase_noise_source(fs, s.phase_noise_dbc_hz, s.phase_noise_offset_hz,
                                                 self.oscillator_seeds[1])
        self.connect(tx, self.channel)
        # Leakage: the transmitted samples through a short causal path, added to each element's echo.
        taps = s.leakage_response()
        self.leakage = None
        if taps:
            self.leakage = filter.fir_filter_ccc(1, taps)
            self.leakage.set_tag_propagation_policy(gr.TPP_DONT)  # the echo path carries the tags
            self.connect(tx, self.leakage)
        #: Each receive element's chain: a dict of its blocks by name.
        self.elements = []
        for k in range(n_receive):
            osc = self.rx_osc
            if k > 0 and own:
                osc = phase_noise_source(fs, s.phase_noise_dbc_hz, s.phase_noise_offset_hz,
                                         self.element_oscillator_seeds[k])
            chain = self._receive_chain(s, fs, (self.channel, k), osc)
            self.connect(chain.pop("out"), (self, k))
            self.elements.append(chain)
        self._set_levels(snr_db)

    def _receive_chain(self, s, fs, rx, osc):
        """One receive element's chain from its echo rx to its converter: the blocks by name,
        and "out", its last port."""
        b = {"rx_osc": osc}
        if self.leakage is not None:
            b["add_leakage"] = blocks.add_cc()
            self.connect(rx, (b["add_leakage"], 0))
            self.connect(self.leakage, (b["add_leakage"], 1))
            rx = (b["add_leakage"], 0)

        # Receiver: down-conversion by the element's oscillator, CFO.
        if osc is not None:
            b["rx_mix"] = blocks.multiply_conjugate_cc()
            self.connect(rx, (b["rx_mix"], 0))
            self.connect(osc, (b["rx_mix"], 1))
            rx = (b["rx_mix"], 0)
        if s.cfo_hz != 0.0:
            b["cfo"] = blocks.rotator_cc(2.0 * math.pi * s.cfo_hz / fs)
            self.connect(rx, b["cfo"])
            rx = (b["cfo"], 0)

        # IQ imbalance: GNU Radio's receiver model, I' = g (I cos p + Q sin p), Q' = Q.
        if s.iq_gain_db != 0.0 or s.iq_phase_deg != 0.0:
            b["iq"] = channels.iqbal_gen(s.iq_gain_db, s.iq_phase_deg, 1)
            # Inside, Q reaches the output both directly and through the adder: keep one copy of each tag.
            b["iq"].adder.set_tag_propagation_policy(gr.TPP_DONT)
            self.connect(rx, b["iq"])
            rx = (b["iq"], 0)

        b["dc"] = None
        if s.dc_offset_db is not None:
            b["dc"] = blocks.add_const_cc(0j)
            self.connect(rx, b["dc"])
            rx = (b["dc"], 0)

        # Sample clock offset: the converter samples at fs (1 + sfo), output k at input time k / (1 + sfo).
        # filter.mmse_resampler_cc's output k is the input at 3 + k * ratio (its 8-tap interpolator's
        # centre): 3 samples of silence ahead of the stream make it k * ratio, so nothing is shifted.
        if s.sfo_ppm != 0.0:
            b["sfo_align"] = blocks.delay(gr.sizeof_gr_complex, _MMSE_CENTRE)
            b["sfo"] = filter.mmse_resampler_cc(0.0, 1.0 / (1.0 + 1e-6 * s.sfo_ppm))
            self.connect(rx, b["sfo_align"], b["sfo"])
            rx = (b["sfo"], 0)

        b["to_scale"] = None
        if s.adc_enob is not None:
            b["to_scale"] = blocks.multiply_const_cc(1.0)  # full scale -> 1 (set_snr_db sets both gains)
            b["to_rails"] = blocks.complex_to_float(1)
            b["clip_i"], b["clip_q"] = analog.rail_ff(-1.0, 1.0), analog.rail_ff(-1.0, 1.0)
            b["clip_q"].set_tag_propagation_policy(gr.TPP_DONT)  # the I rail carries the tags
            # Rounding to 2^(ENOB-1) steps per unit full scale through 32-bit integers
            # (channels.quantizer goes through 16-bit shorts, so above 15 bits it saturates
            # below full scale).
            steps = 2.0 ** (s.adc_enob - 1.0)
            b["quant_i"], b["quant_q"] = (blocks.float_to_int(1, steps), blocks.float_to_int(1, steps))
            b["dequant_i"], b["dequant_q"] = (blocks.int_to_float(1, steps), blocks.int_to_float(1, steps))
            b["from_rails"] = blocks.float_to_complex(1)
            b["from_scale"] = blocks.multiply_const_cc(1.0)
            self.connect(rx, b["to_scale"], b["to_rails"])
            self.connect((b["to_rails"], 0), b["clip_i"], b["quant_i"], b["dequant_i"], (b["from_rails"], 0))
            self.connect((b["to_rails"], 1), b["clip_q"], b["quant_q"], b["dequant_q"], (b["from_rails"], 1))
            self.connect(b["from_rails"], b["from_scale"])
            rx = (b["from_scale"], 0)
        b["out"] = rx
        return b

    def expected_rms(self, snr_db=None):
        """The rms the converter expects (complex, DC included) at an SNR (default: the channel's),
        and the DC's magnitude: (rms, dc)."""
        snr_db = self.channel.snr_db() if snr_db is None else snr_db
        return _expected_rms(self.settings, snr_db, self.tx_power)

    def full_scale(self, snr_db=None):
        """Each rail's full scale in the channel's units at an SNR (default: the channel's):
        converter_full_scale() of this block's settings, 0.0 with an ideal converter."""
        snr_db = self.channel.snr_db() if snr_db is None else snr_db
        return converter_full_scale(self.settings, snr_db, self.tx_power)

    def _set_levels(self, snr_db):
        _, dc = self.expected_rms(snr_db)
        a = self.full_scale(snr_db)  # every element's converter has the same level
        for b in self.elements:
            if b["dc"] is not None:
                b["dc"].set_k(cmath.rect(dc, math.pi / 4))
            if b["to_scale"] is not None:
                b["to_scale"].set_k(1.0 / a)
                b["from_scale"].set_k(a)

    def set_snr_db(self, snr_db):
        """Sets the channel's SNR (from its next frame) and the DC and converter levels (at once)."""
        self.channel.set_snr_db(snr_db)
        self._set_levels(snr_db)

    def snr_db(self):
        """The channel's SNR per resource element in dB."""
        return self.channel.snr_db()
