#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Every example flowgraph against the INSTALLED module, from a folder outside the source tree:
# installs the build into a throw-away prefix, copies the installed examples
# (<prefix>/share/gr-sems/examples; the .grc files only, not the scenes or radio files beside
# them) into another temporary folder, compiles each with grcc and runs each briefly from there
# (the SoapySDR hardware examples compile only; the Qt ones run offscreen, side by side, until
# stopped after a few seconds). Nothing from the source or build tree is on any path: PYTHONPATH and
# GRC_BLOCKS_PATH name the prefix, LD_LIBRARY_PATH is unset (the installed modules find their
# libraries through their RPATH) and the model bundles are found by name in the prefix.
# With "grc" as 4th argument it opens one of them in gnuradio-companion instead (on a virtual
# X display, xvfb-run): GRC must start and load every gr-sems block from the prefix.
#
#   check_installed_examples.sh BUILD_DIR PYTHON_DIR SOURCE_DIR [grc]
set -euo pipefail
build="$1" pydir="$2" src="$3" mode="${4:-run}"
python=/usr/bin/python3
prefix="$(mktemp -d /tmp/sems-prefix.XXXXXX)"
work="$(mktemp -d /tmp/sems-examples.XXXXXX)"
trap 'rm -rf "$prefix" "$work"' EXIT
run_preload="${LD_PRELOAD:-}" # sanitized builds (CMakeLists.txt): whatever imports the module needs it
unset LD_PRELOAD
cmake --install "$build" --prefix "$prefix" > /dev/null
unset SEMS_SOURCE_DIR SEMS_MODELS_PATH LD_LIBRARY_PATH
export PYTHONPATH="$prefix/$pydir"
export GRC_BLOCKS_PATH="$prefix/share/gnuradio/grc/blocks"
fail() { echo "check_installed_examples: $*" >&2; exit 1; }

# Every example of the source tree is installed.
for g in "$src"/examples/*.grc; do
  [ -f "$prefix/share/gr-sems/examples/$(basename "$g")" ] || fail "$(basename "$g") is not installed"
done
cp "$prefix"/share/gr-sems/examples/*.grc "$work/"
cd "$work"

if [ "$mode" = grc ]; then
  command -v xvfb-run > /dev/null || { echo "check_installed_examples: xvfb-run missing (apt-get install xvfb), skipped"; exit 77; }
  # GRC's own loader resolves every block of the flowgraph from the prefix (the GUI would only
  # draw a missing block in red), then the GUI runs until closed: up to 25 s to load the
  # flowgraph (">>> Done"), 3 s more drawing it, then stopped.
  LD_PRELOAD="$run_preload" grcc -o out sems_demo.grc > grcc.log 2>&1 || { cat grcc.log; fail "GRC could not load sems_demo.grc"; }
  # scripts/grc_main_thread: GRC 3.10.5 updates its block tree from a worker thread when its
  # docstrings are loaded; that update is moved to GTK's main loop (see its sitecustomize.py).
  timeout 25 xvfb-run -a env LD_PRELOAD="$run_preload" PYTHONPATH="$src/scripts/grc_main_thread:$PYTHONPATH" \
    gnuradio-companion "$work/sems_demo.grc" > grc.log 2>&1 &
  grc_pid=$!
  for _ in $(seq 100); do grep -q '^>>> Done' grc.log && break; kill -0 "$grc_pid" 2> /dev/null || break; sleep 0.25; done
  grep -q '^>>> Done' grc.log && sleep 3
  kill -TERM "$grc_pid" 2> /dev/null || true # timeout passes it on to its whole process group
  status=0
  wait "$grc_pid" || status=$?
  grep -q '^>>> Done' grc.log || { cat grc.log; fail "gnuradio-companion did not finish loading sems_demo.grc within 25 s (exit $status)"; }
  [ "$status" -eq 124 ] || [ "$status" -eq 143 ] || { cat grc.log; fail "gnuradio-companion exited with $status before it was stopped"; }
  if grep -E "Namespace Gtk not available|Traceback|Block key .* not found|[Ee]rror" grc.log; then
    fail "gnuradio-companion reported the errors above (grc.log)"
  fi
  grep -q "$GRC_BLOCKS_PATH" grc.log || { cat grc.log; fail "gnuradio-companion did not load $GRC_BLOCKS_PATH"; }
  echo "check_installed_examples: gnuradio-companion opened sems_demo.grc with the blocks of $GRC_BLOCKS_PATH"
  exit 0
fi

# The bundles, class libraries and frames by name come from the prefix (a library and a frame
# that exist only there, under names the source tree does not have), and the modules too.
sed 's/"name": "kinematic"/"name": "installed_only"/' "$prefix/share/gr-sems/models/classes/kinematic.json" \
  > "$prefix/share/gr-sems/models/classes/installed_only.json"
sed 's/"name": "sdr_2g4_20mhz"/"name": "installed_only"/' "$prefix/share/gr-sems/models/frames/sdr_2g4_20mhz.json" \
  > "$prefix/share/gr-sems/models/frames/installed_only.json"
LD_PRELOAD="$run_preload" "$python" - "$prefix" <<'PY'
import os, sys
from gnuradio import sems
prefix = os.path.realpath(sys.argv[1])
found = os.path.realpath(sems.model_bundle.find("classifier"))
assert found.startswith(prefix), f"classifier resolved to {found}, not under {prefix}"
assert sems.class_library.find("installed_only").name() == "installed_only"
assert sems.frame_file.find("installed_only").name == "installed_only"
assert os.path.realpath(sems.__file__).startswith(prefix), sems.__file__
maps = open("/proc/self/maps").read().split("\n")
libs = {line.split()[-1] for line in maps if "libgnuradio-sems" in line}
assert libs and all(os.path.realpath(l).startswith(prefix) for l in libs), libs
print("check_installed_examples: bundle 'classifier' ->", found)
PY

run() { # run NAME ARGS...: the compiled flowgraph, at most 300 s
  local name="$1"; shift
  echo "check_installed_examples: $name $*"
  LD_PRELOAD="$run_preload" timeout 300 "$python" -u "out/$name.py" "$@" > "$name.log" 2>&1 \
    || { cat "$name.log"; fail "$name exited with an error"; }
  tail -n 2 "$name.log"
}
# One grcc for every example: GRC loads its blocks once (about 1.7 s per call under the sanitizers).
LD_PRELOAD="$run_preload" grcc -o out *.grc > grcc.log 2>&1 || { cat grcc.log; fail "grcc could not compile every example"; }
for g in *.grc; do
  name="${g%.grc}"
  [ -f "out/$name.py" ] || { cat grcc.log; fail "grcc wrote no out/$name.py for $g"; }
  "$python" -m py_compile "out/$name.py"
done
run sems_chain_snr --frames 200
run sems_demo --frames 200
run sems_demo_td --frames 100
run sems_track_demo --frames 62
run sems_offset_calibration
run sems_record_td --frames 20 --recording rec
run sems_replay_td --recording rec
run sems_record_td --frames 20 --skip 3001 --direct-path 0.5 --recording mid
run sems_replay_sync_td --recording mid
# The sems_radio_* flowgraphs find their radio file in the prefix (none is beside the copied .grc).
run sems_radio_monostatic --frames 20
run sems_radio_bistatic --frames 20
run sems_radio_record --frames 20 --recording radio
run sems_radio_replay --recording radio
# The Qt examples run until closed: offscreen, side by side (they mostly wait on their throttles),
# stopped after 10 s; none may fail or raise before. sems_micro_doppler_live must find its
# scene files in the prefix (none are beside the copied .grc).
qt_examples="sems_live_views sems_micro_doppler_live sems_track_live sems_array_live"
for name in $qt_examples; do
  ( status=0
    QT_QPA_PLATFORM=offscreen LD_PRELOAD="$run_preload" timeout 10 "$python" -u "out/$name.py" \
      > "$name.log" 2>&1 || status=$?
    echo "$status" > "$name.status" ) &
done
wait
for name in $qt_examples; do
  status="$(cat "$name.status")"
  [ "$status" -eq 124 ] || { cat "$name.log"; fail "$name exited with $status before it was stopped"; }
  grep -q Traceback "$name.log" && { cat "$name.log"; fail "$name raised"; }
  echo "check_installed_examples: $name ran 10 s offscreen"
done
echo "check_installed_examples: every example compiled from $work; all but the SoapySDR ones ran against $prefix"
