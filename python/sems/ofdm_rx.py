# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: time-domain samples -> frequency-domain OFDM symbols (docs/design.md §3)."""
import math

from gnuradio import blocks, fft, gr

from .core_python import frame_settings as _frame_settings

_FRAME = _frame_settings()  # the frame defaults' one place (include/gnuradio/sems/core/frame/frame_settings.h)


class ofdm_rx(gr.hier_block2):
    """Time-domain samples to frequency-domain OFDM symbols: cyclic-prefix removal, then an
    M-point FFT, the inverse of ofdm_tx.

    Complex samples in, gr_complex[M] OFDM symbols out: drops the
    cyclic prefix of every M + cp_len samples (blocks.keep_m_in_n), groups the M
    remaining samples into a vector and applies the M-point forward FFT scaled by
    1/sqrt(M) — the inverse of ofdm_tx. The input must start at a symbol boundary
    (no synchronization: this is for files and loop-backs, where timing is known).
    Tags on a symbol's first sample come out on that symbol.
    """

    def __init__(self, n_subcarriers=_FRAME.n_subcarriers, cp_len=_FRAME.cp_len):
        gr.hier_block2.__init__(
            self, "sems_ofdm_rx",
            gr.io_signature(1, 1, gr.sizeof_gr_complex),
            gr.io_signature(1, 1, gr.sizeof_gr_complex * n_subcarriers))
        if n_subcarriers < 1:
            raise ValueError(f"ofdm_rx: n_subcarriers must be >= 1, got {n_subcarriers}")
        if cp_len < 0:
            raise ValueError(f"ofdm_rx: cp_len must be >= 0, got {cp_len}")
        self.n_subcarriers = n_subcarriers
        self.cp_len = cp_len
        scale = [1.0 / math.sqrt(n_subcarriers)] * n_subcarriers  # see ofdm_tx
        self.fft = fft.fft_vcc(n_subcarriers, True, scale, False)
        self.to_vector = blocks.stream_to_vector(gr.sizeof_gr_complex, n_subcarriers)
        if cp_len > 0:
            self.strip_cp = blocks.keep_m_in_n(gr.sizeof_gr_complex, n_subcarriers,
                                               n_subcarriers + cp_len, cp_len)
            self.connect(self, self.strip_cp, self.to_vector, self.fft, self)
        else:
            self.connect(self, self.to_vector, self.fft, self)
