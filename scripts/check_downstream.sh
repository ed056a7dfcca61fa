#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs a built tree into a throw-away prefix, then configures, builds and runs the
# downstream project examples/downstream against that prefix alone (find_package), with
# every installed public header compiled on its own. Usage: check_downstream.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1" src="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
# In a sanitized build (CTest preloads the ASan runtime, CMakeLists.txt) only the program
# needs it: cmake and the compilers run without it (2-3x faster).
run_preload="${LD_PRELOAD:-}"
unset LD_PRELOAD
cmake --install "$build" --prefix "$prefix" > /dev/null
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/examples/downstream" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DSEMS_CHECK_HEADERS=ON -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" > "$work/configure.log" \
  || { cat "$work/configure.log"; exit 1; }
# Every core (getconf: nproc would follow the OMP_NUM_THREADS=1 scripts/test.sh sets for CTest).
cmake --build "$work/build" -j"$(getconf _NPROCESSORS_ONLN)" > "$work/build.log" 2>&1 || { tail -50 "$work/build.log"; exit 1; }
grep -o 'compiling [0-9]* installed headers alone' "$work/configure.log" | sed 's/^/check_downstream: /'
# The libraries come from the prefix only (not the build tree).
LD_PRELOAD="$run_preload" LD_LIBRARY_PATH="$prefix/lib:$prefix/lib/x86_64-linux-gnu" "$work/build/sems_downstream" "$src/models/classifier" 200
if ldd "$work/build/sems_downstream" | grep -q "$build"; then
  echo "check_downstream: the program resolved a library from the build tree" >&2; exit 1
fi
