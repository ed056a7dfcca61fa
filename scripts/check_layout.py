#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the source tree against the map of docs/design.md, "Where things are".

    check_layout.py SOURCE_DIR          the checks below on the repository
    check_layout.py SOURCE_DIR selftest the checks on small made-up trees with known faults

The map is the table of that section: one row per folder, with the library it builds into and
the folders its files may include. A folder under lib/ stands for itself and for its mirror
under include/gnuradio/sems/ (lib/core/frame: also include/gnuradio/sems/core/frame). "may
include" names folders, and what those may include follows (the order is transitive);
"public headers" is every header under include/gnuradio/sems/. It checks:

rows      every folder that holds source files (.cc .h .py .sh .c) has a row with a purpose;
          every row's folder exists; a public header folder has its folder under lib/.
rooms     no folder holds more than 20 source files, nor more than 25 % of the lines of all
          source files.
order     the "may include" arrows have no cycle, and every #include of the project's own
          headers resolves to a file and stays inside what its folder may include. A test
          (qa_*.cc) sits beside what it tests and may include what any folder of its own
          library may (nothing includes a test), plus lib/qa. The library export headers
          (api.h) may be included from anywhere; the generated sems_pydoc.h is not a file of
          the tree.

Prints each problem as FILE:LINE: what, then a summary line; exits 1 if any problem was found.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

SOURCE_EXT = (".cc", ".h", ".py", ".sh", ".c")
MAX_FILES = 20
MAX_LINE_SHARE = 0.25
PUBLIC = "include/gnuradio/sems"
GENERATED = {"sems_pydoc.h"}  # docs/doxygen_pydoc.py writes it into the build tree
SECTION = "## 7. Where things are"
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def read_map(src, problems):
    """The rows of the design page's table: {folder: (library, purpose, [may include])}."""
    path = os.path.join(src, "docs", "design.md")
    rows, in_section = {}, False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if line.startswith("## "):
                in_section = line.strip() == SECTION
                continue
            if not in_section or not line.startswith("| `"):
                continue
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) != 4:
                problems.append(f"docs/design.md:{number}: a row needs 4 cells (folder, library, holds, may include)")
                continue
            folder = cells[0].strip("`").rstrip("/")
            may = [m.strip().strip("`").rstrip("/") for m in cells[3].split(",")]
            may = [m for m in may if m and m != "—"]
            if not cells[2]:
                problems.append(f"docs/design.md:{number}: {folder} has no purpose")
            rows[folder] = (cells[1].strip("`"), cells[2], may, number)
    if not rows:
        problems.append(f"docs/design.md: no table under '{SECTION}'")
    return rows


def tracked_files(src):
    """The repository's files (git's list in a checkout, else every file)."""
    try:
        out = subprocess.run(["git", "-C", src, "ls-files"], capture_output=True, text=True, check=True).stdout
        files = [f for f in out.splitlines() if os.path.isfile(os.path.join(src, f))]
        if files:
            return files
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for root, dirs, names in os.walk(src):
        dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build")]
        files += [os.path.relpath(os.path.join(root, n), src) for n in names]
    return files


def row_of(folder):
    """The map's row for a folder: lib/X for include/gnuradio/sems/X, else the folder itself."""
    if folder == PUBLIC or not folder.startswith(PUBLIC + "/"):
        return folder
    return "lib/" + folder[len(PUBLIC) + 1:]


def closure(rows, problems):
    """Each folder's allowed folders, transitively; reports unknown names and cycles."""
    allowed, state = {}, {}

    def visit(folder, trail):
        if state.get(folder) == "done":
            return allowed[folder]
        if state.get(folder) == "open":
            problems.append(f"docs/design.md:{rows[folder][3]}: the include order has a cycle: "
                            + " -> ".join(trail + [folder]))
            return set()
        state[folder] = "open"
        out = set()
        for m in rows[folder][2]:
            if m == "public headers":
                out.add(m)
            elif m not in rows:
                problems.append(f"docs/design.md:{rows[folder][3]}: {folder} may include '{m}', which has no row")
            else:
                out |= {m} | visit(m, trail + [folder])
        state[folder] = "done"
        allowed[folder] = out
        return out

    for folder in rows:
        visit(folder, [])
    return allowed


def resolve(src, path, kind, name):
    """The repository file an #include names, or None."""
    here = os.path.dirname(path)
    if kind == "<":
        candidates = [os.path.join("include", name)] if name.startswith("gnuradio/sems/") else []
    else:
        candidates = [os.path.join(here, name), os.path.join("lib", name), os.path.join("include", name)]
        if path.startswith("apps/"):
            candidates.append(os.path.join("apps", name))  # apps/CMakeLists.txt: frame_options.h
    for c in candidates:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(src, c)):
            return c
    return None


def check(src):
    problems = []
    rows = read_map(src, problems)
    files = tracked_files(src)
    sources = [f for f in files if f.endswith(SOURCE_EXT)]

    # rows
    folders = {}
    for f in sources:
        folders.setdefault(os.path.dirname(f) or ".", []).append(f)
    for folder in sorted(folders):
        if row_of(folder) not in rows:
            problems.append(f"{folder}/: {len(folders[folder])} source files and no row in docs/design.md ('{SECTION}')")
    for folder, (_, _, _, number) in rows.items():
        if not os.path.isdir(os.path.join(src, folder)):
            problems.append(f"docs/design.md:{number}: {folder}/ does not exist")
    for folder in sorted(folders):
        if folder.startswith(PUBLIC + "/") and not all(os.path.basename(f) == "api.h" for f in folders[folder]):
            mirror = row_of(folder)
            if not os.path.isdir(os.path.join(src, mirror)):
                problems.append(f"{folder}/: public headers without their folder {mirror}/")

    # rooms
    lines = {}
    for f in sources:
        with open(os.path.join(src, f), encoding="utf-8", errors="replace") as fh:
            lines[f] = sum(1 for _ in fh)
    total = sum(lines.values()) or 1
    for folder, fs in sorted(folders.items()):
        if len(fs) > MAX_FILES:
            problems.append(f"{folder}/: {len(fs)} source files (at most {MAX_FILES})")
        share = sum(lines[f] for f in fs) / total
        if share > MAX_LINE_SHARE:
            problems.append(f"{folder}/: {share:.0%} of the module's source lines (at most {MAX_LINE_SHARE:.0%})")

    # order
    allowed = closure(rows, problems)
    library_allowed = {}
    for folder, (library, _, _, _) in rows.items():
        library_allowed.setdefault(library, set()).update({folder} | allowed.get(folder, set()))
    for f in sources:
        if not f.endswith((".cc", ".h", ".c")):
            continue
        mine = row_of(os.path.dirname(f))
        if mine not in rows:
            continue
        ok = {mine} | allowed.get(mine, set())
        if os.path.basename(f).startswith("qa_"):
            ok = ok | library_allowed.get(rows[mine][0], set()) | {"lib/qa"}
        with open(os.path.join(src, f), encoding="utf-8", errors="replace") as fh:
            for number, line in enumerate(fh, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                kind, name = m.groups()
                if kind == "<" and not name.startswith("gnuradio/sems/"):
                    continue  # a system or third-party header
                if os.path.basename(name) in GENERATED:
                    continue
                target = resolve(src, f, kind, name)
                if target is None:
                    problems.append(f"{f}:{number}: #include {name}: no such file in the tree")
                    continue
                if os.path.basename(target) == "api.h":
                    continue
                theirs = row_of(os.path.dirname(target))
                if theirs == mine or theirs in ok:
                    continue
                if "public headers" in ok and target.startswith(PUBLIC + "/"):
                    continue
                problems.append(f"{f}:{number}: {mine}/ includes {name} ({theirs}/), "
                                f"which docs/design.md does not let it include")

    for p in problems:
        print(p)
    print(f"check_layout: {len(rows)} folders mapped, {len(sources)} source files, "
          f"{len(problems)} problem{'s' if len(problems) != 1 else ''}")
    return 1 if problems else 0


def selftest():
    """A small tree that passes, then one fault at a time: each must be reported."""
    table = """# design
## 7. Where things are
| folder | library | what it holds | may include |
|---|---|---|---|
| `lib/core/common` | core | shared helpers | — |
| `lib/core/scene` | core | scenes | `lib/core/common` |
| `lib/learning/nets` | learning | networks | `lib/core/scene` |
| `apps` | — | programs | public headers |
| `include/gnuradio/sems` | core | export header | — |
"""
    # The size rules need a module larger than one folder's share: five padding folders of 60 lines.
    table += "".join(f"| `pad/p{i}` | — | padding | — |\n" for i in range(5)) + "## 8. Next\n"
    base = {f"pad/p{i}/pad.py": "# pad\n" * 60 for i in range(5)}
    base.update({
        "docs/design.md": table,
        "lib/core/common/checks.h": "#pragma once\n",
        "include/gnuradio/sems/core/scene/scene.h": '#include <gnuradio/sems/api.h>\n',
        "include/gnuradio/sems/api.h": "#pragma once\n",
        "lib/core/scene/scene.cc": '#include "core/common/checks.h"\n#include <gnuradio/sems/core/scene/scene.h>\n',
        "lib/core/scene/qa_scene.cc": '#include <gnuradio/sems/core/scene/scene.h>\n',
        "lib/learning/nets/net.cc": '#include <gnuradio/sems/core/scene/scene.h>\n#include <vector>\n',
        "apps/app.cc": '#include <gnuradio/sems/core/scene/scene.h>\n',
    })
    faults = {
        "a kernel including the scene": ({"lib/core/common/checks.h": '#include <gnuradio/sems/core/scene/scene.h>\n'},
                                         "lib/core/common/ includes gnuradio/sems/core/scene/scene.h"),
        "the core including learning": ({"lib/core/scene/scene.cc": '#include "learning/nets/net.h"\n',
                                         "lib/learning/nets/net.h": "#pragma once\n"},
                                        "lib/core/scene/ includes learning/nets/net.h"),
        "a test including another library": ({"lib/core/scene/qa_scene.cc": '#include "learning/nets/net.h"\n',
                                              "lib/learning/nets/net.h": "#pragma once\n"},
                                             "lib/core/scene/ includes learning/nets/net.h"),
        "an app including a private header": ({"apps/app.cc": '#include "core/common/checks.h"\n'},
                                              "apps/ includes core/common/checks.h"),
        "an include that does not resolve": ({"lib/core/scene/scene.cc": '#include "core/scene.h"\n'},
                                             "no such file"),
        "a folder without a row": ({"lib/core/radio/radio.cc": "int x;\n"}, "lib/core/radio/: 1 source files and no row"),
        "a row without a folder": ({"docs/design.md": table.replace("| `apps` |", "| `lib/core/gone` | core | x | — |\n| `apps` |")},
                                   "lib/core/gone/ does not exist"),
        "a cycle": ({"docs/design.md": table.replace("| shared helpers | — |", "| shared helpers | `lib/core/scene` |")},
                    "has a cycle"),
        "too many files": ({f"lib/core/common/f{i}.h": "#pragma once\n" for i in range(20)}, "21 source files (at most 20)"),
        "too many lines": ({"lib/core/common/big.h": "// x\n" * 200}, "of the module's source lines"),
        "headers without their folder": ({"include/gnuradio/sems/core/radio/radio.h": "#pragma once\n"},
                                         "public headers without their folder lib/core/radio/"),
    }
    failures = 0
    for name, (change, expected) in [("a tree without faults", ({}, None))] + list(faults.items()):
        with tempfile.TemporaryDirectory() as d:
            for path, text in {**base, **change}.items():
                os.makedirs(os.path.join(d, os.path.dirname(path)), exist_ok=True)
                with open(os.path.join(d, path), "w", encoding="utf-8") as f:
                    f.write(text)
            r = subprocess.run([sys.executable, os.path.abspath(__file__), d], capture_output=True, text=True)
            if expected is None:
                good = r.returncode == 0
            else:
                good = r.returncode == 1 and expected in r.stdout
            if not good:
                failures += 1
                print(f"selftest: {name}: expected {'a pass' if expected is None else repr(expected)}, got:\n{r.stdout}")
    print(f"check_layout selftest: {len(faults) + 1 - failures} passed, {failures} failed")
    return 1 if failures else 0


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) >= 2 else 2
    src = os.path.abspath(sys.argv[1])
    if len(sys.argv) > 2 and sys.argv[2] == "selftest":
        return selftest()
    return check(src)


if __name__ == "__main__":
    sys.exit(main())
