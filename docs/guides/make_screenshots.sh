#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes the screenshots of docs/guides/grc.md: GNU Radio Companion opened on example
# flowgraphs under a virtual X display, and the running Qt live views.
#
#   bash docs/guides/make_screenshots.sh [BUILD_DIR]      (default ./build, built)
#
# Needs xvfb, imagemagick and GTK's introspection data (installed with apt-get when missing).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
out="$root/docs/guides/img"
case "${1:-}" in -h|--help) sed -n '3,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
[ -d "$build/python_pkg/gnuradio/sems" ] || { echo "make_screenshots: no built gnuradio.sems in $build/python_pkg" >&2; exit 2; }
if ! command -v xvfb-run >/dev/null || ! command -v import >/dev/null || [ ! -e /usr/lib/x86_64-linux-gnu/girepository-1.0/Gtk-3.0.typelib ]; then
  apt-get install -y --no-install-recommends xvfb imagemagick gir1.2-gtk-3.0
fi
mkdir -p "$out"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
export PYTHONPATH="$build/python_pkg${PYTHONPATH:+:$PYTHONPATH}" GRC_BLOCKS_PATH="$root/grc" SEMS_SOURCE_DIR="$root"
export GRC_PREFS_PATH="$tmp/grc.conf"

# One GRC window of W x H on a screen of the same size, the block tree narrow and the
# console short, the flowgraph given in $1, saved as $2 (cropped to the window).
grc_shot() {
  local grc="$1" png="$2" w="${3:-1920}" h="${4:-1080}"
  cat > "$GRC_PREFS_PATH" <<EOF
[main]
main_window_width = $w
main_window_height = $h
console_window_position = $((h - 180))
blocks_window_position = $((w - 170))
variable_editor_sidebar = False
EOF
  cat > "$tmp/shot.sh" <<EOF
#!/bin/bash
gnuradio-companion "$grc" > "$tmp/grc.log" 2>&1 &
pid=\$!
sleep 25
import -window root "$png"
kill \$pid
EOF
  chmod +x "$tmp/shot.sh"
  xvfb-run -a -s "-screen 0 ${w}x${h}x24" "$tmp/shot.sh"
  echo "wrote $png"
}

grc_shot "$root/examples/sems_demo.grc" "$out/grc_demo.png" 1920 1000
grc_shot "$root/examples/sems_demo_td.grc" "$out/grc_demo_td.png" 1920 1000
grc_shot "$root/examples/sems_live_views.grc" "$out/grc_live_views.png" 2600 1200

# The running Qt views, offscreen (the same command as the example's test).
QT_QPA_PLATFORM=offscreen /usr/bin/python3 "$root/examples/screenshot_qt.py" \
  "$root/examples/sems_live_views.grc" "$tmp/qt" "$out/live_views_running.png" \
  --seconds 8 --size 1500x900 --check "tb.classifier.frames() >= 3 and tb.delay.frames() >= 3"
echo "wrote $out/live_views_running.png"
