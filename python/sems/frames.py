# SPDX-License-Identifier: GPL-3.0-or-later
"""The frame a block works on, from what a user types: `frame_of`.

Every GRC block whose parameters include the frame (N, M, B, f_c, T, the prefix, the guards)
takes one *Frame* parameter (the leakage canceller's window and the phase-noise source's sample
rate are numbers of their own), resolved by this function (or, in the sinks' C++, by the same
`frame_file.find`), so a preset name, a frame file and the default mean the same thing in every
block and in Python.
"""
from .core_python import frame_file, frame_settings


def frame_of(frame="", cp_len=-1):
    """The frame_settings a frame names.

    frame: a preset's name (``paper``, ``sdr_2g4_20mhz``, ...), a frame file (format
    ``sems.frame``), '' for the default frame (the paper's), or a frame_settings, which is
    returned as it is. Names are found as ``sems.frame_file.find`` finds them
    (docs/reference/frame_files.md).
    cp_len: a cyclic prefix (samples) that replaces the frame's when >= 0; -1 keeps it. For a
    time-domain link run with another prefix than its frame's; the frame's other fields stay.

    Raises ValueError naming the frame when it is found nowhere (with every place searched)
    or its file is bad, and TypeError for anything but a string or a frame_settings.
    """
    if isinstance(frame, frame_settings):
        fs = frame
    elif isinstance(frame, str):
        try:
            fs = frame_file.find(frame).frame
        except ValueError as e:  # frame_file.find's message names the frame and the places searched
            raise ValueError(f"frame_of: {e}") from None
    else:
        raise TypeError(f"frame_of: frame must be a preset name, a frame file or a frame_settings, "
                        f"got {type(frame).__name__} {frame!r}")
    if cp_len is None or int(cp_len) < 0:
        return fs
    try:
        return frame_settings(fs.n_symbols, fs.n_subcarriers, fs.bandwidth_hz, fs.carrier_hz,
                              fs.symbol_interval_s, int(cp_len), fs.guard_subcarriers)
    except ValueError as e:
        raise ValueError(f"frame_of: frame {frame if isinstance(frame, str) else 'given'!r} "
                         f"with cyclic prefix {cp_len}: {e}") from None
