# SPDX-License-Identifier: GPL-3.0-or-later
"""gr-sems: semantic sensing over OFDM for GNU Radio.

Core (always loaded, no LibTorch): frame_settings, pilot_mask, scene, channel_model,
keys, front_end_settings, front_end_frame; frame_of (a frame by name or file); blocks pilot_mapper, target_channel, target_channel_td, frame_sync,
leakage_canceller, cfo_corrector, pilot_extractor, range_doppler_map, range_angle_map, phase_noise_source; hier
blocks ofdm_tx / ofdm_rx / radio_front_end.

Learning (LibTorch, loaded on first use of one of these names): classifier_sink,
delay_estimator_sink, model_bundle, bundle_decoder, training_settings, train, ...
Baselines (loaded on first use): periodogram / OMP / MUSIC delay estimators, delay_crb,
doppler_features, feature_svm, ...

A flowgraph of mapper, channel and extractor therefore never maps LibTorch into the
process; `import gnuradio.sems.learning_python` loads it explicitly.
"""
import importlib as _importlib

from .core_python import *  # noqa: F401,F403

from .frames import frame_of  # noqa: F401
from .ofdm_tx import ofdm_tx  # noqa: F401
from .ofdm_rx import ofdm_rx  # noqa: F401
from .radio_front_end import (converter_full_scale, radio_front_end, radio_settings,  # noqa: F401
                              recorded_full_scale, write_recording_info)

# The names of the lazily loaded extensions (qa_lazy_import checks these lists against
# the modules, so a name bound in C++ and missing here fails a test).
_LAZY_MODULES = {
    "learning_python": (
        "task_kind", "task_name", "task_from_name", "model_bundle", "bundle_decoder",
        "training_settings", "training_result", "train", "classifier_sink",
        "delay_estimator_sink", "sink_defaults", "classifier_chirp_rates",
        "track_training_settings", "track_training_result", "train_track", "track_state", "track_classifier",
        "position_sink", "position_training_settings", "position_training_result", "train_position",
        "position_estimate", "position_estimator",
        "mimo_mask_settings", "mimo_mask_result", "mimo_mean_crb_rad2", "learn_mimo_mask",
    ),
    "baselines_python": (
        "delay_search", "slow_time_model", "periodogram_delay_estimator",
        "omp_delay_estimator", "music_delay_estimator", "delay_crb", "doppler_features",
        "feature_svm", "random_subcarrier_mask", "nested_subcarrier_mask",
        "angle_search", "angle_crb_rad2", "array_beamformer", "beamform_pilots", "beamforming_angle_estimator", "capon_angle_estimator", "music_angle_estimator",
        "mimo_angle_crb_rad2", "mimo_ml_estimate", "mimo_ml_angle_estimator",
    ),
}
_LAZY_NAMES = {name: module for module, names in _LAZY_MODULES.items() for name in names}


def __getattr__(name):
    """PEP 562: import the extension that binds `name` on its first use."""
    module = _LAZY_NAMES.get(name)
    if module is None:
        raise AttributeError("module 'gnuradio.sems' has no attribute %r" % (name,))
    value = getattr(_importlib.import_module("." + module, __name__), name)
    globals()[name] = value  # later look-ups do not come back here
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY_NAMES))
