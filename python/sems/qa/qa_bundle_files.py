#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A model bundle's files are the ones its bundle.json names (mask_file, weights_file),
not fixed names: a bundle with renamed files loads and answers exactly like the original,
and a name that leaves the bundle directory is refused naming the key."""
import json
import os
import shutil
import tempfile
import unittest

import numpy as np

from gnuradio import gr_unittest
from gnuradio import sems

SRC = os.environ.get("SEMS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLASSIFIER = os.path.join(SRC, "models", "classifier")


class qa_bundle_files(gr_unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="sems_bundle_files_")

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def renamed_copy(self, mask_name, weights_name):
        """The shipped classifier with its mask and weights under other names."""
        d = os.path.join(self.tmp, "renamed")
        os.mkdir(d)
        with open(os.path.join(CLASSIFIER, "bundle.json")) as f:
            j = json.load(f)
        shutil.copy(os.path.join(CLASSIFIER, j.get("mask_file", "mask.json")), os.path.join(d, mask_name))
        shutil.copy(os.path.join(CLASSIFIER, j.get("weights_file", "decoder.pt")), os.path.join(d, weights_name))
        j["mask_file"], j["weights_file"] = mask_name, weights_name
        with open(os.path.join(d, "bundle.json"), "w") as f:
            json.dump(j, f)
        return d

    def test_renamed_files_are_read(self):
        d = self.renamed_copy("pilots_v2.json", "weights_v2.pt")
        self.assertFalse(os.path.exists(os.path.join(d, "decoder.pt")))
        self.assertFalse(os.path.exists(os.path.join(d, "mask.json")))
        b = sems.model_bundle.load(d)
        self.assertEqual(b.mask_name, "pilots_v2.json")
        self.assertEqual(b.weights_name, "weights_v2.pt")
        self.assertEqual(b.weights_path(), os.path.join(d, "weights_v2.pt"))
        ref = sems.bundle_decoder(CLASSIFIER, 1)
        dec = sems.bundle_decoder(d, 1)
        rng = np.random.default_rng(7)
        n_p = ref.n_pilots()
        obs = (rng.standard_normal((5, n_p)) + 1j * rng.standard_normal((5, n_p))).astype(np.complex64)
        np.testing.assert_array_equal(dec.classify(obs), ref.classify(obs))  # same weights, bit-exact
        # Saving keeps the recorded names.
        b2 = json.loads(b.to_json_string())
        self.assertEqual((b2["mask_file"], b2["weights_file"]), ("pilots_v2.json", "weights_v2.pt"))

    def test_missing_named_weights_are_reported_by_name(self):
        d = self.renamed_copy("mask.json", "weights_v2.pt")
        os.remove(os.path.join(d, "weights_v2.pt"))
        shutil.copy(os.path.join(CLASSIFIER, "decoder.pt"), os.path.join(d, "decoder.pt"))  # not the named one
        with self.assertRaisesRegex(ValueError, "weights_v2.pt"):
            sems.bundle_decoder(d, 1)

    def test_names_outside_the_bundle_are_refused(self):
        d = self.renamed_copy("mask.json", "decoder.pt")
        with open(os.path.join(d, "bundle.json")) as f:
            j = json.load(f)
        for key in ("weights_file", "mask_file"):
            for bad in ("../decoder.pt", "sub/x.pt", ""):
                jj = dict(j)
                jj[key] = bad
                with open(os.path.join(d, "bundle.json"), "w") as f:
                    json.dump(jj, f)
                with self.assertRaisesRegex(ValueError, key + ".*file name inside the bundle directory"):
                    sems.model_bundle.load(d)

    def test_defaults_without_keys(self):
        # Bundles without the keys read mask.json and decoder.pt.
        d = self.renamed_copy("mask.json", "decoder.pt")
        with open(os.path.join(d, "bundle.json")) as f:
            j = json.load(f)
        del j["mask_file"], j["weights_file"]
        with open(os.path.join(d, "bundle.json"), "w") as f:
            json.dump(j, f)
        b = sems.model_bundle.load(d)
        self.assertEqual((b.mask_name, b.weights_name), ("mask.json", "decoder.pt"))


if __name__ == "__main__":
    gr_unittest.run(qa_bundle_files)
