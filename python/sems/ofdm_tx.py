# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: frequency-domain OFDM symbols -> time-domain samples (docs/design.md §3)."""
import math

from gnuradio import blocks, digital, fft, gr

from .core_python import frame_settings as _frame_settings

_FRAME = _frame_settings()  # the frame defaults' one place (include/gnuradio/sems/core/frame/frame_settings.h)


class ofdm_tx(gr.hier_block2):
    """Frequency-domain OFDM symbols to time-domain samples: an M-point inverse FFT, then a
    cyclic prefix of cp_len samples.

    gr_complex[M] OFDM symbols in, complex samples out, with GNU Radio's own blocks
    (fft.fft_vcc, digital.ofdm_cyclic_prefixer).

    The inverse FFT is scaled by 1/sqrt(M) (unitary), so a symbol keeps its power in
    the time domain and ofdm_rx (forward FFT, also 1/sqrt(M)) undoes it exactly.
    Each symbol becomes M + cp_len samples; the prefix is the symbol's last cp_len samples.
    Tags on a symbol come out on its first sample (the start of its prefix).
    """

    def __init__(self, n_subcarriers=_FRAME.n_subcarriers, cp_len=_FRAME.cp_len):
        gr.hier_block2.__init__(
            self, "sems_ofdm_tx",
            gr.io_signature(1, 1, gr.sizeof_gr_complex * n_subcarriers),
            gr.io_signature(1, 1, gr.sizeof_gr_complex))
        if n_subcarriers < 1:
            raise ValueError(f"ofdm_tx: n_subcarriers must be >= 1, got {n_subcarriers}")
        if cp_len < 0:
            raise ValueError(f"ofdm_tx: cp_len must be >= 0, got {cp_len}")
        self.n_subcarriers = n_subcarriers
        self.cp_len = cp_len
        # fft_vcc multiplies its input by the window before transforming: a constant
        # window of 1/sqrt(M) is the unitary scaling, without another block.
        scale = [1.0 / math.sqrt(n_subcarriers)] * n_subcarriers
        self.ifft = fft.fft_vcc(n_subcarriers, False, scale, False)
        if cp_len > 0:
            self.cp = digital.ofdm_cyclic_prefixer(n_subcarriers, n_subcarriers + cp_len)
            # Without a length-tag key the prefixer copies every tag itself AND lets the
            # scheduler propagate it, so each tag came out twice: keep only its own copy.
            self.cp.set_tag_propagation_policy(gr.TPP_DONT)
        else:  # the prefixer refuses a zero prefix: just serialize
            self.cp = blocks.vector_to_stream(gr.sizeof_gr_complex, n_subcarriers)
        self.connect(self, self.ifft, self.cp, self)
