#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A bundle parameter may be a bare name (`classifier`): model_bundle.find() resolves it from
any working directory, in the documented order (the path as given, $SEMS_MODELS_PATH, the
source tree's models/, the installed data folder), and an unknown name is refused with every
place it looked."""
import os
import shutil
import tempfile

from gnuradio import gr_unittest, sems

SOURCE = os.path.realpath(os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "..")))
MODELS = os.path.join(SOURCE, "models")


class qa_bundle_search(gr_unittest.TestCase):

    def setUp(self):
        self.cwd = os.getcwd()
        self.env = {k: os.environ.get(k) for k in ("SEMS_MODELS_PATH", "SEMS_SOURCE_DIR")}
        self.tmp = tempfile.mkdtemp()
        os.chdir(self.tmp)  # outside the source tree
        os.environ["SEMS_SOURCE_DIR"] = SOURCE
        os.environ.pop("SEMS_MODELS_PATH", None)

    def tearDown(self):
        os.chdir(self.cwd)
        for k, v in self.env.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        shutil.rmtree(self.tmp)

    def test_001_bare_name_from_another_folder(self):
        self.assertEqual(os.path.realpath(sems.model_bundle.find("classifier")), os.path.join(MODELS, "classifier"))
        b = sems.model_bundle.load("delay_single")
        self.assertEqual(os.path.realpath(b.directory), os.path.join(MODELS, "delay_single"))
        sink = sems.classifier_sink("classifier", 32)  # the GRC default, from a folder of its own
        self.assertEqual(list(sink.class_names()), ["pedestrian", "car", "drone"])

    def test_002_order(self):
        # $SEMS_MODELS_PATH comes before the source tree; the path as given before both.
        mine = os.path.join(self.tmp, "mine")
        shutil.copytree(os.path.join(MODELS, "classifier_fast"), os.path.join(mine, "classifier"))
        os.environ["SEMS_MODELS_PATH"] = "/nonexistent/first:" + mine
        self.assertEqual(sems.model_bundle.find("classifier"), os.path.join(mine, "classifier"))
        self.assertEqual(sems.model_bundle.search_path()[:2], ["/nonexistent/first", mine])
        # A folder of that name in the working directory is taken as given, before both; one
        # without a bundle.json that hides a bundle of the search path is refused, naming both.
        os.makedirs("classifier")
        with self.assertRaises(ValueError) as e:
            sems.model_bundle.find("classifier")
        self.assertIn("classifier: the folder of that name in the working directory is taken as given and holds no bundle.json",
                      str(e.exception))
        self.assertIn(os.path.join(mine, "classifier") + ": give that path", str(e.exception))
        shutil.copy(os.path.join(MODELS, "classifier_fast", "bundle.json"), "classifier")
        self.assertEqual(sems.model_bundle.find("classifier"), "classifier")
        # A folder no bundle of the search path is named like is taken as given (load() then
        # names its missing bundle.json).
        os.makedirs("my_bundle")
        self.assertEqual(sems.model_bundle.find("my_bundle"), "my_bundle")

    def test_003_unknown_name_lists_every_place(self):
        os.environ["SEMS_MODELS_PATH"] = "/nonexistent/models"
        with self.assertRaises(ValueError) as e:
            sems.model_bundle.load("no_such_bundle")
        msg = str(e.exception)
        self.assertIn("no_such_bundle (as given, working directory", msg)
        for folder in sems.model_bundle.search_path():
            self.assertIn(os.path.join(folder, "no_such_bundle"), msg)
        self.assertIn("/nonexistent/models/no_such_bundle", msg)
        self.assertIn(os.path.join(MODELS, "no_such_bundle"), msg)
        self.assertIn("share/gr-sems/models/no_such_bundle", msg)  # the installed data folder
        with self.assertRaisesRegex(ValueError, "classifier_sink: cannot load model bundle: no_such_bundle"):
            sems.classifier_sink("no_such_bundle", 32)
        # An absolute path is taken as given, never searched.
        with self.assertRaisesRegex(ValueError, "/nonexistent/classifier: model bundle directory does not exist"):
            sems.model_bundle.find("/nonexistent/classifier")


if __name__ == "__main__":
    gr_unittest.run(qa_bundle_search)
