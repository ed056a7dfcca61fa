#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python docstrings carry the headers' Doxygen text (docs/doxygen_pydoc.py, one source).

Each checked name's __doc__ must contain the \\brief of its declaration in the public header,
read here from the header itself, so a docstring that drifts from the header fails.
"""
import os
import re
import unittest

from gnuradio import gr_unittest
from gnuradio import sems

SOURCE = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
INCLUDE = os.path.join(SOURCE, "include", "gnuradio", "sems")


def header_brief(header, declaration):
    """The \\brief of the Doxygen block right before `declaration` in `header`, whitespace-normalised."""
    with open(os.path.join(INCLUDE, header)) as f:
        text = f.read()
    at = text.index(declaration)
    start = text.rindex("/*!", 0, at)
    block = text[start:at]
    m = re.search(r"\\brief\s+(.*?)(?:\n\s*\*\s*\n|\\details|\\param|\\return|\\throws|\*/)", block, re.S)
    assert m, f"{header}: no \\brief before {declaration!r}"
    return " ".join(m.group(1).replace("*", " ").split()) if "*/" not in m.group(1) else None


def normalise(doc):
    return " ".join((doc or "").split())


class qa_docstrings(gr_unittest.TestCase):
    def check(self, obj, header, declaration):
        brief = header_brief(header, declaration)
        self.assertTrue(brief, f"{header}: empty brief")
        self.assertIn(brief, normalise(obj.__doc__), f"{obj!r}: docstring lacks the header's \\brief")

    def test_blocks(self):
        self.check(sems.target_channel, "blocks/target_channel.h", "class SEMS_API target_channel")
        self.check(sems.pilot_mapper, "blocks/pilot_mapper.h", "class SEMS_API pilot_mapper")
        self.check(sems.pilot_extractor, "blocks/pilot_extractor.h", "class SEMS_API pilot_extractor")
        self.check(sems.phase_noise_source, "blocks/phase_noise_source.h", "class SEMS_API phase_noise_source")

    def test_core(self):
        self.check(sems.frame_settings, "core/frame/frame_settings.h", "struct SEMS_API frame_settings")
        self.check(sems.front_end_settings, "core/radio/front_end.h", "struct SEMS_API front_end_settings")
        self.check(sems.phase_noise_process, "core/radio/phase_noise.h", "class SEMS_API phase_noise_process")
        self.check(sems.channel_model, "core/channel/channel_model.h", "class SEMS_API channel_model")
        self.check(sems.scene, "core/scene/scene.h", "class SEMS_API scene")
        self.check(sems.class_library, "core/scene/class_library.h", "class SEMS_API class_library")
        self.check(sems.class_definition, "core/scene/class_library.h", "struct SEMS_API class_definition")
        self.check(sems.rotor_motion, "core/scene/micro_motion.h", "struct SEMS_API rotor_motion")
        self.check(sems.walker_motion, "core/scene/micro_motion.h", "struct SEMS_API walker_motion")
        self.check(sems.wheels_motion, "core/scene/micro_motion.h", "struct SEMS_API wheels_motion")
        self.check(sems.scatterers_motion, "core/scene/micro_motion.h", "struct SEMS_API scatterers_motion")
        self.check(sems.scatterer_body, "core/channel/channel_model.h", "struct SEMS_API scatterer_body")
        self.check(sems.track_spec, "core/scene/scene.h", "struct SEMS_API track_spec")
        self.check(sems.array_geometry, "core/array/array_geometry.h", "class SEMS_API array_geometry")
        self.check(sems.steering_vector, "core/array/steering.h", "steering_vector(const array_geometry& a")
        self.check(sems.micro_motion_model, "core/scene/micro_motion.h", "SEMS_API std::string micro_motion_model")
        self.check(sems.class_library.find, "core/scene/class_library.h", "static std::shared_ptr<const class_library> find")

    def test_learning(self):
        # The learning names load lazily: this also checks the lazy module keeps its docs.
        self.check(sems.classifier_sink, "learning/sinks/classifier_sink.h", "class SEMS_LEARNING_API classifier_sink")
        self.check(sems.delay_estimator_sink, "learning/sinks/delay_estimator_sink.h",
                   "class SEMS_LEARNING_API delay_estimator_sink")
        self.check(sems.model_bundle, "learning/bundles/model_bundle.h", "struct SEMS_LEARNING_API model_bundle")

    def test_baselines(self):
        self.check(sems.periodogram_delay_estimator, "baselines/periodogram_delay_estimator.h",
                   "class SEMS_BASELINES_API periodogram_delay_estimator")

    def test_make_parameters(self):
        # make()'s \param text reaches the constructor's docstring.
        doc = normalise(sems.target_channel.__init__.__doc__)
        self.assertIn("snr_db: SNR per resource element, +inf = noiseless", doc)
        self.assertIn("Raises:", doc)
        doc = normalise(sems.classifier_sink.__init__.__doc__)
        self.assertIn("batch_size: frames per inference call (>= 1)", doc)

    def test_method(self):
        doc = normalise(sems.pilot_mapper.set_pilot_power.__doc__)
        self.assertIn("Sets E_p from the next frame.", doc)


if __name__ == "__main__":
    gr_unittest.run(qa_docstrings)
