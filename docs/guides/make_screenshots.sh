#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes the screenshots the docs show: GNU Radio Companion opened on example flowgraphs under
# a virtual X display (docs/guides/img/grc_*.png), and the running Qt examples
# (docs/results/live_views.png, docs/results/sems_track_live.png,
# docs/reference/micro_doppler_live.png, docs/reference/array_live.png).
#
#   bash docs/guides/make_screenshots.sh [BUILD_DIR]      (default ./build, built; as root)
#
# Needs xvfb, imagemagick and GTK's introspection data (installed with apt-get when missing).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
case "${1:-}" in -h|--help) sed -n '3,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
build="$(cd "${1:-$root/build}" && pwd)"
out="$root/docs/guides/img"
[ -d "$build/python_pkg/gnuradio/sems" ] || { echo "make_screenshots: no built gnuradio.sems in $build/python_pkg" >&2; exit 2; }
if ! command -v xvfb-run >/dev/null || ! command -v import >/dev/null || [ ! -e /usr/lib/x86_64-linux-gnu/girepository-1.0/Gtk-3.0.typelib ]; then
  apt-get install -y --no-install-recommends xvfb imagemagick gir1.2-gtk-3.0
fi
mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# The running Qt examples: their tests (examples/CMakeLists.txt: the stress cycles, then the run
# with its checks) save the screenshots into the build tree. The two 1200-pixel windows get
# fonts at 108 dpi instead of 96, to read at page width; the live views fill their 1500 pixels
# at 96 already.
ctest --test-dir "$build" --output-on-failure -R '^example_sems_live_views$'
QT_FONT_DPI=108 ctest --test-dir "$build" --output-on-failure -R '^example_sems_(micro_doppler_live|track_live|array_live)$'
cp "$build/examples/sems_live_views.png" "$root/docs/results/live_views.png"
cp "$build/examples/sems_track_live.png" "$root/docs/results/sems_track_live.png"
cp "$build/examples/sems_micro_doppler_live.png" "$root/docs/reference/micro_doppler_live.png"
cp "$build/examples/sems_array_live.png" "$root/docs/reference/array_live.png"
echo "wrote docs/results/live_views.png docs/results/sems_track_live.png docs/reference/micro_doppler_live.png docs/reference/array_live.png"

# GRC as a user sees it after `cmake --install build` to /usr/local: the build installed into a
# throw-away prefix that a private mount namespace shows at /usr/local, so that GRC's console
# and the variables' values name the install, not this machine's folders.
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" > /dev/null
pydir="$(cd "$prefix" && dirname "$(dirname "$(find . -path '*/gnuradio/sems/__init__.py' | head -n 1)")")"
pydir="${pydir#./}"

# One GRC window of W x H on a screen of the same size (the block tree narrow, the console two
# lines high), opened on the installed example $1 and saved as $2: without the block tree, and
# cut into vertical strips of at most 900 pixels stacked top to bottom (left strip first), so
# that the flowgraph reads at page width.
grc_shot() {
  local grc="$1" png="$2" w="$3" h="$4"
  cat > "$tmp/grc.conf" <<EOF
[main]
main_window_width = $w
main_window_height = $h
console_window_position = $((h - 90))
blocks_window_position = $((w - 150))
variable_editor_sidebar = False
EOF
  cat > "$tmp/shot.sh" <<EOF
#!/bin/bash
mount --bind "$prefix" /usr/local
export PYTHONPATH=/usr/local/$pydir GRC_BLOCKS_PATH=/usr/local/share/gnuradio/grc/blocks GRC_PREFS_PATH="$tmp/grc.conf"
unset SEMS_SOURCE_DIR SEMS_MODELS_PATH
cd /usr/local/share/gr-sems/examples
xvfb-run -a -s "-screen 0 ${w}x${h}x24" bash -c 'gnuradio-companion "$grc" > "$tmp/grc.log" 2>&1 & pid=\$!; sleep 25; import -window root "$png"; kill \$pid'
EOF
  unshare --mount --propagation private bash "$tmp/shot.sh"
  local strips=$(( (w - 150 + 899) / 900 ))
  convert "$png" -crop "$((w - 150))x${h}+0+0" +repage -crop "${strips}x1@" +repage \
    -bordercolor '#808080' -border 0x2 -append "$png"
  echo "wrote ${png#"$root"/}"
}

grc_shot sems_demo.grc "$out/grc_demo.png" 1950 760
grc_shot sems_demo_td.grc "$out/grc_demo_td.png" 1950 760
grc_shot sems_live_views.grc "$out/grc_live_views.png" 2600 1000
grc_shot sems_array_live.grc "$out/grc_array_live.png" 1950 760
