# SPDX-License-Identifier: GPL-3.0-or-later
"""Batches of (H, truth) from the core channel model, for building data sets in Python.

The frames are the ones the emulator block and the training app draw: the same C++
channel_model, the same seed, the same frames.
"""
import numpy as np

from .core_python import channel_model, frame_settings, keys


def channel_batches(scene, batch_size, n_batches=None, seed=0, settings=None, snr_db=None,
                    first_frame=0):
    """Yield (H, truths) batches: H is batch_size x N x M complex64, truths a list of dicts.

    With snr_db set, the arrays are noisy observations Y = H + V (pilot symbol 1, unit
    power) instead of H, drawn by the same model's noise generator. n_batches=None
    yields forever; frame indices continue from batch to batch.
    """
    if batch_size < 1:
        raise ValueError("channel_batches: batch_size must be >= 1, got %r" % (batch_size,))
    model = channel_model(settings or frame_settings(), scene, seed)
    frame = first_frame
    produced = 0
    while n_batches is None or produced < n_batches:
        h, truths = model.generate(batch_size, frame)
        if snr_db is not None:
            model.add_noise(h, float(snr_db))
            for t in truths:
                t[keys.snr_db] = float(snr_db)
        yield h, truths
        frame += batch_size
        produced += 1


def stack_truths(truths, key):
    """One truth field of a batch as a numpy array, e.g. stack_truths(t, 'class')."""
    return np.array([t[key] for t in truths])
