#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs a built tree into a throw-away prefix and checks that the installed module
# imports and runs from there alone: headers, libraries, CMake package, GRC blocks, the model
# bundles (found by name), and no LD_LIBRARY_PATH (the installed Python modules and apps find
# the libraries through their RPATH). Usage: check_install.sh BUILD_DIR PYTHON_DIR PYTHON
set -euo pipefail
build="$1" pydir="$2" python="$3"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
for f in include/gnuradio/sems/core/channel/channel_model.h include/gnuradio/sems/learning/networks/network_settings.h \
    lib/cmake/gnuradio-sems/gnuradio-semsConfig.cmake share/gnuradio/grc/blocks/sems_target_channel.block.yml \
    share/gr-sems/models/classifier/bundle.json share/gr-sems/models/delay_single/decoder.pt; do
  [ -f "$prefix/$f" ] || { echo "check_install: $f was not installed"; exit 1; }
done
cd "$prefix"   # nothing from the source or build tree on the path
unset LD_LIBRARY_PATH SEMS_SOURCE_DIR SEMS_MODELS_PATH
PYTHONPATH="$prefix/$pydir" "$python" - "$prefix" <<'PY'
import gnuradio.sems as sems, os, sys
assert os.environ["PYTHONPATH"] in sems.__file__, sems.__file__
h, truths = sems.channel_model(sems.frame_settings(), sems.scene.random(), 1).generate(2)
assert h.shape == (2, 32, 64) and len(truths) == 2
# A bundle by name: the installed one, from any folder; an unknown name lists the places searched.
prefix = os.path.realpath(sys.argv[1])
found = os.path.realpath(sems.model_bundle.find("delay_single"))
assert found == os.path.join(prefix, "share/gr-sems/models/delay_single"), found
sink = sems.classifier_sink("classifier", 32)
try:
    sems.model_bundle.load("no_such_bundle")
    raise SystemExit("check_install: an unknown bundle name was accepted")
except ValueError as e:
    assert os.path.join(prefix, "share/gr-sems/models/no_such_bundle") in str(e), str(e)
print("check_install: installed module imports from", os.path.dirname(sems.__file__), "and finds its models in", os.path.dirname(found))
PY
if [ -x "$prefix/bin/sems_train" ]; then
  "$prefix/bin/sems_train" --help > /dev/null || { echo "check_install: the installed sems_train does not start"; exit 1; }
fi
