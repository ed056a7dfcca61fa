#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""sems.front_end_frame (what sems_train --radio draws) against the streaming chain it models:
ofdm samples -> SemS Radio Front End -> SemS Leakage Canceller (told the converter's full
scale) -> FFT. For each radio, the error the impairments add to the resource elements, relative
to the same channel through the ideal radio, has the same power in both."""
import json
import math
import os

import numpy as np
from gnuradio import blocks, gr, gr_unittest

from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
RADIOS = os.path.join(SOURCE, "examples", "radios")
N, M, CP = 32, 64, 16
S = M + CP
RANGE_M = 50.0  # a still target at delay index 10, past the canceller's taps
SNR_DB = 40.0   # the channel's noise well under the impairments


def still_target():
    return json.dumps({"format": "sems.scene", "version": 1, "fading": "none",
                       "targets": [{"class": "car", "range_m": RANGE_M, "velocity_mps": 0.0, "power": 1,
                                    "paths": [{"excess_range_m": 0, "power": 1}]}]})


def qpsk(frames, seed):
    rng = np.random.default_rng(seed)
    return (((rng.integers(0, 2, (frames * N, M)) * 2 - 1) + 1j * (rng.integers(0, 2, (frames * N, M)) * 2 - 1))
            / math.sqrt(2))


def streamed_grid(settings, x_sym, seed):
    """Y/X per resource element after the streaming chain (frames*N x M)."""
    t = np.fft.ifft(x_sym, axis=1) * math.sqrt(M)
    x = np.concatenate([t[:, -CP:], t], axis=1).ravel().astype(np.complex64)
    fe = sems.radio_front_end(scene=still_target(), snr_db=SNR_DB, seed=seed, n_symbols=N, n_subcarriers=M,
                              cp_len=CP, **settings)
    tb = gr.top_block()
    src, tx = blocks.vector_source_c(x.tolist()), blocks.vector_source_c(x.tolist())
    sink = blocks.vector_sink_c()
    if fe.settings.oscillator == sems.oscillator_kind.shared and (fe.settings.leakage_db is not None
                                                                  or fe.settings.dc_offset_db is not None):
        canc = sems.leakage_canceller(window=N * S, clip_level=fe.full_scale(),
                                      taps=max(4, fe.settings.leakage_taps))
        tb.connect(src, fe, (canc, 0))
        tb.connect(tx, (canc, 1))
        tb.connect(canc, sink)
    else:
        tb.connect(src, fe, sink)
    tb.run()
    y = np.array(sink.data(), dtype=np.complex64).reshape(-1, S)[:, CP:]
    return np.fft.fft(y, axis=1) / math.sqrt(M) / x_sym


def added_error(y, ref, skip):
    """E|y - c ref|^2 / E|ref|^2 over the frames after the first `skip`, c the least-squares
    gain of each frame: a decoder takes a frame's complex gain as unknown, so the phase the
    oscillators have wandered to by the frame's start is not an error (a stream's grows
    without bound, the model starts each frame one frame after its oscillators)."""
    y, ref = y.reshape(-1, N * M)[skip:], ref.reshape(-1, N * M)[skip:]
    c = np.sum(np.conj(ref) * y, axis=1) / np.sum(np.abs(ref) ** 2, axis=1)
    return np.mean(np.abs(y - c[:, None] * ref) ** 2) / np.mean(np.abs(ref) ** 2)


class qa_front_end_frame(gr_unittest.TestCase):

    def check_radio(self, settings, frames=40, rel=0.25):
        seed = 11
        x_sym = qpsk(frames, 3)
        ideal = streamed_grid({}, x_sym, seed)
        streamed = added_error(streamed_grid(settings, x_sym, seed), ideal, 4)  # the canceller settled
        # The same channel per frame (the ideal stream's H = Y/X, noise 40 dB down) through the model.
        radio = sems.radio_settings("", **settings)
        model = sems.front_end_frame(sems.frame_settings(), radio)
        h = ideal.reshape(frames, N, M)
        modelled = np.stack([model.observe(h[f], RANGE_M / 5.0, 10 ** (-SNR_DB / 10), 100 + f) for f in range(frames)])
        frame_err = added_error(modelled, ideal, 4)
        self.assertGreater(streamed, 1e-4, msg=f"{settings}: the radio adds an error")
        self.assertAlmostEqual(frame_err / streamed, 1.0, delta=rel,
                               msg=f"{settings}: streamed {streamed:.3e}, front_end_frame {frame_err:.3e}")
        return streamed, frame_err

    def test_monostatic_sdr(self):
        """The example's monostatic radio: leakage, shared phase noise, IQ, DC, 12 bits, canceller."""
        with open(os.path.join(RADIOS, "sdr_monostatic.json")) as f:
            text = f.read()
        radio = sems.front_end_settings.parse(text)
        self.check_radio(dict(leakage_db=radio.leakage_db, phase_noise_dbc_hz=radio.phase_noise_dbc_hz,
                              iq_gain_db=radio.iq_gain_db, iq_phase_deg=radio.iq_phase_deg,
                              dc_offset_db=radio.dc_offset_db, adc_enob=radio.adc_enob))

    def test_leakage_through_a_converter(self):
        """Leakage 40 dB over the echo sets the 12-bit converter's level: its rounding and the
        canceller's steady state, alike."""
        self.check_radio(dict(leakage_db=40.0, adc_enob=12.0))

    def test_iq_imbalance(self):
        self.check_radio(dict(iq_gain_db=1.0, iq_phase_deg=5.0))

    def test_converter(self):
        self.check_radio(dict(adc_enob=6.0))

    def test_separate_oscillators(self):
        self.check_radio(dict(oscillator="separate", phase_noise_dbc_hz=-95.0, cfo_hz=200.0))


if __name__ == "__main__":
    gr_unittest.run(qa_front_end_frame)
