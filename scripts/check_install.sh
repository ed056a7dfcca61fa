#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs a built tree into a throw-away prefix and checks that the installed module
# imports and runs from there alone. Usage: check_install.sh BUILD_DIR PYTHON_DIR PYTHON
set -euo pipefail
build="$1" pydir="$2" python="$3"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
for f in include/gnuradio/sems/core/channel_model.h include/gnuradio/sems/learning/network_settings.h lib/cmake/gnuradio-sems/gnuradio-semsConfig.cmake share/gnuradio/grc/blocks/sems_target_channel.block.yml; do
  [ -f "$prefix/$f" ] || { echo "check_install: $f was not installed"; exit 1; }
done
cd "$prefix"   # nothing from the source or build tree on the path
PYTHONPATH="$prefix/$pydir" LD_LIBRARY_PATH="$prefix/lib:$prefix/lib/x86_64-linux-gnu" "$python" - <<'PY'
import gnuradio.sems as sems, os
assert os.environ["PYTHONPATH"] in sems.__file__, sems.__file__
h, truths = sems.channel_model(sems.frame_settings(), sems.scene.random(), 1).generate(2)
assert h.shape == (2, 32, 64) and len(truths) == 2
print("check_install: installed module imports from", os.path.dirname(sems.__file__))
PY
