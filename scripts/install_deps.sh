#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the Debian 12 packages gr-sems builds, tests and runs with. Needs root.
set -euo pipefail
packages=(
  build-essential cmake pkg-config git
  gnuradio gnuradio-dev libvolk2-dev libspdlog-dev libfmt-dev libgmp-dev
  # gnuradio-companion's GTK 3 bindings: Debian's gnuradio package does not pull them in, and
  # without them GRC stops at start ("Namespace Gtk not available").
  gir1.2-gtk-3.0
  # A virtual X display: the test install_grc_opens starts gnuradio-companion headless.
  xvfb xauth
  libtorch-dev libgloo-dev
  # Debian's LibTorch calls BLAS through libblas.so.3: without OpenBLAS that is the reference
  # (netlib) BLAS, and training runs 3.3x slower (sgemm_ was 70 % of a training profile).
  # The OpenMP build shares LibTorch's OpenMP threads (no oversubscription between sinks).
  libopenblas0-openmp
  libcppunit-dev pybind11-dev python3-pybind11
  nlohmann-json3-dev libboost-program-options-dev libeigen3-dev libsvm-dev zlib1g-dev
  python3-numpy python3-scipy python3-matplotlib python3-yaml python3-mako
  # The decoders' anchor: the same networks in PyTorch from Python (apps/benchmarks/torch_reference.py;
  # the tests torch_reference_matches and bench_quick).
  python3-torch
  # The time-domain emulator's peer in sems_bench (gr-radar's static_target_simulator_cc).
  gr-radar
  doxygen
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
