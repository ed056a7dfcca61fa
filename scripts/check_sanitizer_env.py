#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that every CTest test of an AddressSanitizer tree preloads the sanitizer runtime.

A test that starts /usr/bin/python3 (or any uninstrumented program) and then loads the
instrumented library fails with "ASan runtime does not come first" unless LD_PRELOAD names
the runtime; each CMakeLists.txt calls sems_sanitizer_env() after its last add_test for that.
This check names every test that lacks it.

Usage: check_sanitizer_env.py BUILD_DIR
"""
import json
import subprocess
import sys


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: check_sanitizer_env.py BUILD_DIR")
    build = sys.argv[1]
    out = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1"],
                         check=True, capture_output=True, text=True).stdout
    missing = []
    for test in json.loads(out)["tests"]:
        env = []
        for prop in test.get("properties", []):
            if prop["name"] == "ENVIRONMENT":
                env = prop["value"]
        if not any(e.startswith("LD_PRELOAD=") and "asan" in e for e in env):
            missing.append(test["name"])
    if missing:
        sys.exit(f"{build}: {len(missing)} test(s) run without the sanitizer runtime in "
                 f"LD_PRELOAD (call sems_sanitizer_env() after their add_test): "
                 + ", ".join(missing))
    print(f"{build}: every test preloads the sanitizer runtime")


if __name__ == "__main__":
    main()
