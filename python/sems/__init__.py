"""gr-sems: semantic sensing over OFDM for GNU Radio.

Blocks: pilot_mapper, target_channel, pilot_extractor, classifier_sink,
delay_estimator_sink; hier blocks ofdm_tx / ofdm_rx. Core: frame_settings,
pilot_mask, scene, channel_model (see the C++ headers in include/gnuradio/sems).
"""
from .sems_python import *  # noqa: F401,F403

from .ofdm_tx import ofdm_tx  # noqa: F401
from .ofdm_rx import ofdm_rx  # noqa: F401
