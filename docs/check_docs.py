#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the user documentation against the repository.

    check_docs.py SOURCE_DIR [--build BUILD_DIR] links|commands|wording|numbers|facts|snippets|selftest

links     every image and link a document gives (README.md, CHANGELOG.md, models/README.md,
          examples/README.md, docs/**/*.md outside docs/results/notes/) resolves to a file or
          folder of the repository, every #anchor into a Markdown file names one of its
          headings, every path in backticks that starts with a top-level folder exists, and
          no document is longer than 400 lines.
commands  every command a document gives in a code block whose program is under apps/,
          scripts/ or build/apps/ exists and answers --help with exit status 0. Built apps
          are checked only when BUILD_DIR has them (skipped, with a message, otherwise).
          Shell scripts without a --help option are checked for syntax only (bash -n).
wording   the documents above and the comments and messages of the code (lib/, include/,
          python/, apps/, grc/, examples/, scripts/, and the scripts under docs/) speak to
          users: no issue numbers, no runs named by letter, no "met"/"not met" verdicts
          against targets, no work sessions, no dates or commit hashes of our own runs, no
          design file outside the repository; every docs/, models/ or examples/ page the
          code names exists. The user documents (not CHANGELOG.md) also tell no history of our
          runs: no other jobs or load of the machine a figure was measured on, no earlier,
          first or prototype run, no fix and what came before it (RUN_HISTORY). The logs and
          data files under docs/ and models/ (.log, .csv, .json, .txt) name no folder of the
          machine that wrote them (/work/..., /home/..., /root/..., /tmp/...): MACHINE_PATH.

numbers   a number stated by hand lives in one document: no decimal number with three or more
          significant digits (98.87, 0.0255, 61.5) and no digit-grouped integer (15 308) appears
          in the prose of two of README.md, models/README.md and docs/**/*.md (outside
          docs/results/notes/ and the generated tables, GENERATED). Code blocks, inline code
          and software versions (GNU Radio 3.10) are not read; powers of two are sizes, not
          measurements. Values that two documents state as different facts are listed, with
          the documents and the reason, in NUMBERS_ALLOWED. Repeats within one document are
          not reported.

facts     what the pages state about defaults and shipped files (the frame's defaults, the
          examples' cyclic prefixes, the masks' subcarriers, bundle keys, presets, radios, block
          and trainer defaults, limits) equals what the files say: FACTS, a table of (page,
          pattern, how to compute the true value from models/, examples/, grc/ and the headers).

snippets  every Python or shell code block of README.md and docs/ (outside docs/results/notes/
          and the generated docs/reference/blocks/) is either marked as an excerpt, with
          <!-- excerpt --> as the last non-blank line before it, or listed in RUNNABLE; the
          runnable ones (Python only) run, each page's in page order as one script, with
          /usr/bin/python3 on BUILD_DIR's staged package.

selftest  runs the checks on a small made-up repository with known faults.

Prints each problem as FILE:LINE: what, then a summary line; exits 1 if any problem was found.
"""
import argparse
import ast
import functools
import glob
import os
import re
import shlex
import subprocess
import sys

TOP_FOLDERS = ("apps", "cmake", "docs", "examples", "fuzz", "grc", "include", "lib", "models",
               "python", "scripts")
NOTES = os.path.join("docs", "results", "notes")
MAX_LINES = 400  # a user document longer than this is split

# Files another change rewrites; listed so the check names them instead of failing on them.
# Remove an entry once its file is clean.
LINK_PENDING = {"docs/guides/install.md"}  # written by the install change
WORDING_PENDING = {
}
# Run history in a user document: what a figure's machine was busy with, the runs and fixes
# behind it. It belongs in docs/results/notes/; the page keeps what a user needs.
RUN_HISTORY = [
    (re.compile(r"\b(?:from|while|beside|with) (?:\w+ )?other jobs\b"), "the jobs that shared the machine"),
    (re.compile(r"\bload ~\s?\d"), "the machine's load during a run"),
    (re.compile(r"\b(?:before|after) the fix\b", re.I), "a fix and what came before it"),
    (re.compile(r"\ban? (?:earlier|first|previous|prototype) run\b", re.I), "an earlier run"),
    (re.compile(r"(?:^|[.(]\s*)Before, "), "what the code did before"),
    (re.compile(r"\bused to (?:be|give|take|hold|read|return|compute|run|make)\b"), "what the code used to do"),
    (re.compile(r"\bthe binary that ran\b|\bbuilt before\b"), "an earlier binary"),
    (re.compile(r"\ban earlier layout\b|\bthis layout\b"), "an earlier layout"),
]
HISTORY_EXEMPT = {"CHANGELOG.md"}        # history is what a changelog is for
# A folder of the machine a log or data file was written on: the reader's machine has none of
# them, so a committed record names paths relative to the repository (models/classifier) or
# to the run's own output folder (out/eval_full/...).
MACHINE_PATH = re.compile(r"(?<![\w.~-])/(?:work|home|root|tmp|mnt|scratch)/[^\s,\"')]*")
DATA_FILES = (".log", ".csv", ".json", ".txt")
HISTORY_PENDING = set()   # pages another change rewrites: their run history is reported, not failed

MONTHS = r"(?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Sept|Oct|Nov|Dec)[a-z]*\.?"
PROCESS_TALK = [
    (re.compile(r"\bissues? #?\d+", re.I), "an issue number"),
    (re.compile(r"(?<![\w(/&#\[\"'])#\d+(?![\w-])"), "an issue number (#N)"),
    (re.compile(r"\bruns? [A-F]\b"), "a run named by letter"),
    (re.compile(r"\bnot met\b", re.I), "a 'not met' verdict"),
    (re.compile(r"\bmet:", re.I), "a 'met:' verdict"),
    (re.compile(r"\bthis session\b|\bsessions? \d+\b|\bsession-\d+\b", re.I), "a work session"),
    (re.compile(r"\bDESIGN(?:\.md| §| section)"), "a design file that is not in the repository (docs/design.md)"),
    (re.compile(r"\b20\d\d-[01]\d-[0-3][\dx]\b"), "a date"),
    (re.compile(r"(?<![\w.\-/])(?=[0-9a-f]{0,39}[a-f])(?=[0-9a-f]{0,39}\d)[0-9a-f]{7,40}(?![\w\-])"), "a commit hash"),
    (re.compile(r"\b" + MONTHS + r" [0-3]?[\dx]\b(?!\s*(?:Hz|dB|m\b|ms|s\b|%))"), "a date"),
]


# Tables written by a script from a run's CSV or log: they own their numbers, and prose elsewhere
# links to them. The numbers check reads only the hand-written documents.
GENERATED = {
    "docs/results/tables.md",             # apps/figures/plot_results.py (scripts/evaluation/eval_full.sh)
    "docs/results/kinematic_tables.md",   # apps/figures/plot_kinematic.py (scripts/evaluation/eval_kinematic.sh)
    "docs/results/td_accuracy.md",        # apps/evaluation/sems_td_accuracy.py
    "docs/results/scaling_tables.md",     # apps/benchmarks/sems_bench_scaling.py --table
    "docs/results/radio_sweep_table.md",  # apps/evaluation/sems_radio_sweep.py --table
    "docs/results/learned_vs_hand.md",    # docs/results/learned_vs_hand.py table
    "docs/results/track_classifier_kinematic_track.md",  # apps/figures/plot_track.py (the bundle's bundle.json)
    "docs/results/walker_pair_bound.md",  # docs/results/walker_pair_bound.py
    "docs/results/claims.md",             # apps/figures/claims.py (scripts/evaluation/eval_full.sh, eval_kinematic.sh)
    "docs/results/claims_kinematic.md",   # apps/figures/claims.py, beside claims.md
    "docs/results/range_table.md",        # apps/figures/plot_range.py (sems_eval --exp7-parts range)
    "docs/results/track_tables.md",       # apps/figures/plot_tracks.py (scripts/evaluation/eval_tracks.sh)
    "docs/results/track_pilots.md",       # apps/figures/plot_tracks.py (scripts/evaluation/eval_tracks.sh)
    "docs/results/exp8_nr/track_tables.md",  # apps/figures/plot_tracks.py (scripts/evaluation/eval_tracks_nr.sh)
    "docs/results/exp9_angle.md",         # apps/figures/plot_angle.py (scripts/evaluation/eval_arrays.sh)
    "docs/results/exp9_classes.md",       # apps/figures/plot_array_classes.py (scripts/evaluation/eval_arrays.sh)
    "docs/results/exp9_mimo.md",          # apps/figures/plot_mimo.py (scripts/evaluation/eval_arrays.sh)
    "docs/results/adult_child_track.md",  # apps/figures/pair_tracks.py (scripts/evaluation/eval_adult_child.sh)
    "docs/pareto/pareto.md",              # apps/evaluation/sems_pareto.py
    "models/README.md",                   # scripts/models_catalogue.py (the bundles' model_card.json)
    "docs/reference/walker_kinematics.md",  # docs/reference/walker_signature.py
    "docs/reference/walker_timing.md",      # docs/reference/walker_signature.py
}

# The same digits in two documents that state two different facts: value -> (documents, why).
# The check passes while a value occurs only in (a subset of) its documents.
NUMBERS_ALLOWED = {
    "0.143": ({"docs/reference/time_domain.md", "docs/reference/walker.md"},
              "a 0.143 m delay error in a time-domain table; the walker's foot, 0.143 of the height"),
    "12.5": ({"docs/guides/radio_front_end.md", "docs/reference/micro_doppler_gallery.md",
              "docs/reference/walker.md"},
             "a residual of 12.5 dB; a car's 12.5 m/s; a wavelength of 12.5 mm"),
    "52.5": ({"docs/guides/radio_front_end.md", "docs/reference/hardening.md"},
             "a residual of 52.5 dB; 52.5 s of user time"),
}
NUMBER = re.compile(r"(?<![\w.,/#])(\d{1,3}(?:[ \u2009\u202f]\d{3})+(?:\.\d+)?|\d+\.\d+)(?![\w.]\d|\w)")
VERSION_OF = re.compile(r"(?:GNU Radio|LibTorch|PyTorch|Python|python3-torch|Debian|CMake|Doxygen|version)\s*$")


DOC_PAGE = re.compile(r"(?<![\w/])((?:docs|models|examples)/[\w/.-]*\w\.md)\b")


def documents(src):
    """The user documents, as paths relative to src."""
    docs = ["README.md", "CHANGELOG.md", "models/README.md", "examples/README.md"]
    for path in sorted(glob.glob(os.path.join(src, "docs", "**", "*.md"), recursive=True)):
        rel = os.path.relpath(path, src)
        if not rel.startswith(NOTES + os.sep):
            docs.append(rel)
    return [d for d in docs if os.path.isfile(os.path.join(src, d))]


def code_files(src):
    exts = (".cc", ".h", ".py", ".sh", ".yml", ".grc", ".in", ".cmake", ".txt")
    out = []
    for top in ("lib", "include", "python", "apps", "grc", "examples", "scripts", "docs"):
        for root, _, files in os.walk(os.path.join(src, top)):
            rel_root = os.path.relpath(root, src)
            if rel_root.startswith(NOTES):
                continue
            for f in files:
                if f.endswith(exts) or f in ("sems_bench",):
                    out.append(os.path.join(rel_root, f))
    return sorted(out)


def slug(heading):
    """GitHub's anchor for a Markdown heading."""
    h = re.sub(r"[`*]", "", heading.strip().lower())
    h = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", h)
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        found = set()
        in_code = False
        for line in open(path, encoding="utf-8"):
            if line.startswith("```"):
                in_code = not in_code
            elif not in_code and re.match(r"#{1,6} ", line):
                base = slug(line.lstrip("#"))
                n, a = 0, base
                while a in found:
                    n += 1
                    a = f"{base}-{n}"
                found.add(a)
        cache[path] = found
    return cache[path]


def prose_lines(text):
    """(line number, line, in a code block) for every line of a Markdown text."""
    in_fence = False
    for i, line in enumerate(text.split("\n"), 1):
        if line.lstrip().startswith("```"):
            in_fence = not in_fence
            yield i, line, True
            continue
        yield i, line, in_fence or line.startswith("    ")


LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
IMG_TAG = re.compile(r"<img [^>]*src=\"([^\"]+)\"")
BACKTICK_PATH = re.compile(r"`((?:%s)/[^`\s]*)`" % "|".join(TOP_FOLDERS))


def check_links(src, problems, skipped):
    checked = 0
    for doc in documents(src):
        text = open(os.path.join(src, doc), encoding="utf-8").read()
        if text.count("\n") > MAX_LINES:
            problems.append(f"{doc}: {text.count(chr(10))} lines, more than {MAX_LINES}: move long studies to {NOTES}/")
        base = os.path.dirname(os.path.join(src, doc))
        for n, line, code in prose_lines(text):
            if code:
                continue
            targets = LINK.findall(line) + IMG_TAG.findall(line)
            for t in targets:
                if re.match(r"^[a-z]+:", t):  # http:, https:, mailto:
                    continue
                checked += 1
                path, _, anchor = t.partition("#")
                full = os.path.normpath(os.path.join(base, path)) if path else os.path.join(src, doc)
                if os.path.relpath(full, src) in LINK_PENDING and not os.path.exists(full):
                    skipped.append(f"{doc}:{n}: link to {t}: page written by another change, not checked")
                elif not os.path.exists(full):
                    problems.append(f"{doc}:{n}: link to {t}: no such file")
                elif not os.path.realpath(full).startswith(os.path.realpath(src)):
                    problems.append(f"{doc}:{n}: link to {t}: outside the repository")
                elif anchor and full.endswith(".md") and anchor not in anchors(full):
                    problems.append(f"{doc}:{n}: link to {t}: no heading with anchor #{anchor}")
            for p in BACKTICK_PATH.findall(line):
                if re.search(r"[<>*{}$]|\.\.\.|…|[A-Z]{3,}", p):  # a pattern or placeholder, not a path
                    continue
                checked += 1
                p = os.path.join(src, p.rstrip("/").rstrip(".,;:"))
                if not os.path.exists(p) and not glob.glob(glob.escape(p) + ".*"):  # apps/x: apps/x.cc
                    problems.append(f"{doc}:{n}: path `{os.path.relpath(p, src)}`: not in the repository")
    return checked


ENV = re.compile(r"^[A-Z_][A-Z0-9_]*=\S*$")
WRAPPERS = {"nice", "time", "bash", "sh", "/usr/bin/python3", "python3", "sudo", "env"}


def doc_commands(src):
    """(doc, line, program, the variables the command sets before it) for every command in a
    code block whose program is ours."""
    for doc in documents(src):
        text = open(os.path.join(src, doc), encoding="utf-8").read()
        for n, line, code in prose_lines(text):
            if not code:
                continue
            s = line.strip()
            if not s or s.startswith(("#", "```", "$ ", ">", "|")):
                continue
            try:
                words = shlex.split(s, comments=True)
            except ValueError:
                words = s.split()
            env = set()
            while words and (ENV.match(words[0]) or words[0] in WRAPPERS or words[0].startswith("-")):
                if ENV.match(words[0]):
                    env.add(words[0].split("=", 1)[0])
                words.pop(0)
            if words and re.match(r"^(build/apps/[\w.\-/]+|(apps|scripts|docs)/[\w.\-/]+\.(py|sh))$", words[0]):
                yield doc, n, words[0], env


def imports_sems_at_top(path):
    """True when the script's module body imports gnuradio.sems: run from the build tree it
    needs the staged package on PYTHONPATH (check_commands sets it itself, so its --help run
    would not notice a command without it)."""
    try:
        tree = ast.parse(open(path, encoding="utf-8").read())
    except SyntaxError:
        return False
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module == "gnuradio" and any(a.name == "sems" for a in node.names):
            return True
        if isinstance(node, ast.Import) and any(a.name.startswith("gnuradio.sems") for a in node.names):
            return True
    return False


def check_commands(src, build, problems, skipped):
    seen = {}
    for doc, n, prog, env_set in doc_commands(src):
        seen.setdefault(prog, (doc, n))
        path = os.path.join(src, prog)
        if prog.endswith(".py") and os.path.isfile(path) and "PYTHONPATH" not in env_set and imports_sems_at_top(path):
            problems.append(f"{doc}:{n}: {prog} imports gnuradio.sems: the command needs "
                            "PYTHONPATH=build/python_pkg (or the installed module)")
    env = dict(os.environ)
    if build and os.path.isdir(os.path.join(build, "python_pkg")):
        env["PYTHONPATH"] = os.path.join(build, "python_pkg") + os.pathsep + env.get("PYTHONPATH", "")
    env["SEMS_SOURCE_DIR"] = src
    for prog, (doc, n) in sorted(seen.items()):
        where = f"{doc}:{n}"
        if prog.startswith("build/"):
            if not build or not os.path.isdir(os.path.join(build, "apps")):
                skipped.append(f"{where}: {prog}: no build tree given, not checked")
                continue
            path = os.path.join(build, prog[len("build/"):])
            if not os.path.exists(path):
                skipped.append(f"{where}: {prog}: not built in {build}, not checked")
                continue
        else:
            path = os.path.join(src, prog)
            if not os.path.isfile(path):
                problems.append(f"{where}: {prog}: no such file in the repository")
                continue
        if path.endswith(".sh"):
            body = open(path, encoding="utf-8").read()
            r = subprocess.run(["bash", "-n", path], capture_output=True, text=True)
            if r.returncode != 0:
                problems.append(f"{where}: {prog}: bash -n: {r.stderr.strip()}")
                continue
            if "--help" not in body:
                skipped.append(f"{where}: {prog}: has no --help option; syntax checked only")
                continue
            cmd = ["bash", path, "--help"]
        elif path.endswith(".py"):
            body = open(path, encoding="utf-8").read()
            if "argparse" not in body and "--help" not in body:
                r = subprocess.run(["/usr/bin/python3", "-m", "py_compile", path], capture_output=True, text=True)
                if r.returncode != 0:
                    problems.append(f"{where}: {prog}: py_compile: {r.stderr.strip()}")
                else:
                    skipped.append(f"{where}: {prog}: has no --help option; syntax checked only")
                continue
            cmd = ["/usr/bin/python3", path, "--help"]
        else:
            cmd = [path, "--help"]
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env, cwd=src)
        except subprocess.TimeoutExpired:
            problems.append(f"{where}: {prog} --help: did not finish in 120 s")
            continue
        out = (r.stdout + r.stderr).strip()
        if r.returncode != 0 and path.endswith(".py") and re.search(r"No module named 'gnuradio.sems'|cannot import name 'sems'", out) \
                and not (build and os.path.isdir(os.path.join(build, "python_pkg"))):
            skipped.append(f"{where}: {prog}: needs the built gnuradio.sems (no build tree given)")
            continue
        if r.returncode != 0:
            last = out.splitlines()[-1] if out else "(no output)"
            problems.append(f"{where}: {prog} --help: exit status {r.returncode}: {last}")
        elif not out:
            problems.append(f"{where}: {prog} --help: printed nothing")
    return len(seen)


def check_wording(src, problems, skipped):
    files = [(d, True) for d in documents(src)] + [(c, False) for c in code_files(src)]
    for rel, is_doc in files:
        if rel == "docs/check_docs.py":  # states the patterns
            continue
        if rel in WORDING_PENDING:
            skipped.append(f"{rel}: being rewritten by another change, not checked")
            continue
        try:
            text = open(os.path.join(src, rel), encoding="utf-8").read()
        except UnicodeDecodeError:
            continue
        for n, line in enumerate(text.split("\n"), 1):
            for page in ([] if is_doc else DOC_PAGE.findall(line)):
                if page not in LINK_PENDING and not os.path.exists(os.path.join(src, page)):
                    problems.append(f"{rel}:{n}: names {page}, which is not in the repository")
            for pattern, what in PROCESS_TALK:
                m = pattern.search(line)
                if m:
                    problems.append(f"{rel}:{n}: {what} ('{m.group(0)}'): {line.strip()[:120]}")
                    break
            for pattern, what in ([] if not is_doc or rel in HISTORY_EXEMPT else RUN_HISTORY):
                m = pattern.search(line)
                if m:
                    (skipped if rel in HISTORY_PENDING else problems).append(
                        f"{rel}:{n}: run history, {what} ('{m.group(0).strip()}'): keep what a user needs, move "
                        f"the rest under docs/results/: {line.strip()[:100]}")
                    break
    for rel in data_files(src):
        with open(os.path.join(src, rel), encoding="utf-8", errors="replace") as f:
            for n, line in enumerate(f, 1):
                m = MACHINE_PATH.search(line)
                if m:
                    problems.append(f"{rel}:{n}: a folder of the machine that wrote it ('{m.group(0)[:60]}'): "
                                    "name it relative to the repository or the run's output folder")
                    break
    return len(files)


def data_files(src):
    """The committed logs and data files of docs/ and models/ (build trees excluded)."""
    out = []
    for top in ("docs", "models"):
        for root, dirs, names in os.walk(os.path.join(src, top)):
            dirs[:] = sorted(d for d in dirs if not d.startswith("build") and d != "__pycache__")
            out += [os.path.relpath(os.path.join(root, n), src) for n in sorted(names) if n.endswith(DATA_FILES)]
    return out


def significant_digits(value):
    """3 for 0.0255 and 98.9, 4 for 1.000; an integer's trailing zeros do not count (30 000: 1)."""
    digits = value.replace(".", "").lstrip("0")
    return len(digits if "." in value else digits.rstrip("0"))


def stated_numbers(text):
    """(value, line) of every number the prose of a Markdown text states that the numbers
    check compares: decimals with 3+ significant digits and digit-grouped integers with 3+
    that are not powers of two; code, inline code, link targets, HTML and versions skipped."""
    # A block between <!-- name --> and <!-- /name --> is a table a script writes (and CTest
    # checks against its source, e.g. scripts/link_budget_table.py): it owns its numbers.
    text = re.sub(r"<!-- (\w+) -->.*?<!-- /\1 -->", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r"<!--.*?-->", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    prose = []
    for _, line, code in prose_lines(text):
        if code:
            prose.append("")
            continue
        line = re.sub(r"`[^`]*`", " ", line)
        line = re.sub(r"\]\([^)]*\)", "]", line)
        prose.append(re.sub(r"<[A-Za-z/!][^>]*>", " ", line))  # tags, not "|α|² < 0.02 ... > 0.5"
    prose = "\n".join(prose)
    for m in NUMBER.finditer(prose):
        value = re.sub(r"\s", "", m.group(1))
        if significant_digits(value) < 3 or VERSION_OF.search(prose[max(0, m.start() - 30):m.start()]):
            continue
        if "." not in value and int(value) & (int(value) - 1) == 0:  # 4 096: a size
            continue
        yield value, prose.count("\n", 0, m.start()) + 1


def check_numbers(src, problems, skipped, generated=None):
    generated = GENERATED if generated is None else generated
    docs = [d for d in documents(src)
            if d not in generated and d not in ("CHANGELOG.md", "examples/README.md")]
    where = {}  # value -> {doc: first line}
    for doc in docs:
        for value, n in stated_numbers(open(os.path.join(src, doc), encoding="utf-8").read()):
            where.setdefault(value, {}).setdefault(doc, n)
    for value, places in sorted(where.items()):
        allowed = NUMBERS_ALLOWED.get(value, (set(), ""))[0]
        if len(places) > 1 and not set(places) <= allowed:
            first, *others = sorted(places.items())
            problems.append(f"{first[0]}:{first[1]}: {value} is also stated by hand in "
                            + ", ".join(f"{d}:{n}" for d, n in others)
                            + ": keep it in the document (or generated table) that owns it and link there")
    for value, (allowed, _) in sorted(NUMBERS_ALLOWED.items()):
        if len(where.get(value, {})) < 2:
            skipped.append(f"NUMBERS_ALLOWED['{value}']: no longer in two documents; the entry can go")
    return len(docs)


# ---- facts: what the pages state about defaults and shipped files, against the files ----------

FRAME_H = "include/gnuradio/sems/core/frame/frame_settings.h"
TRAINER_H = "include/gnuradio/sems/learning/training/trainer.h"
LIMITS_H = "include/gnuradio/sems/core/common/limits.h"
MOTION_H = "include/gnuradio/sems/core/scene/micro_motion.h"
LINK_BUDGET_H = "include/gnuradio/sems/core/scene/link_budget.h"
C_MPS = 3e8  # design.md §1: c = 3·10⁸ m/s exactly
NUMBER_WORDS = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five", 6: "six", 7: "seven",
                8: "eight", 9: "nine", 10: "ten", 11: "eleven", 12: "twelve"}


def header_default(src, header, name):
    """The default a header gives a field or constant: `int cp_len = 16;` -> 16.0."""
    text = open(os.path.join(src, header), encoding="utf-8").read()
    m = re.search(r"\b%s\s*=\s*([-+0-9.eE]+)\s*;" % re.escape(name), text)
    if not m:
        raise LookupError(f"{header}: no default for {name}")
    return float(m.group(1))


def struct_default(src, header, struct, name):
    """The default of a field of one struct of a header (several structs may share the name)."""
    text = open(os.path.join(src, header), encoding="utf-8").read()
    m = re.search(r"\bstruct (?:SEMS_API )?%s\b.*?\n};" % re.escape(struct), text, re.S)
    if not m:
        raise LookupError(f"{header}: no struct {struct}")
    v = re.search(r"\b%s\s*=\s*([-+0-9.eE]+)\s*;" % re.escape(name), m.group(0))
    if not v:
        raise LookupError(f"{header}: {struct} has no default for {name}")
    return float(v.group(1))


def frame_default(src, name):
    return header_default(src, FRAME_H, name)


def load_json(src, rel):
    import json
    return json.load(open(os.path.join(src, rel), encoding="utf-8"))


def mask_pilots(src, bundle):
    """Every [n, m] of a bundle's mask.json (all frames of a super-frame file)."""
    d = load_json(src, f"models/{bundle}/mask.json")
    sets = [f["pilots"] for f in d["frames"]] if "frames" in d else [d["pilots"]]
    return [tuple(p) for s in sets for p in s]


def mask_subcarriers(src, bundle):
    return sorted({m for _, m in mask_pilots(src, bundle)})


def bundles(src, task=None):
    out = []
    for path in sorted(glob.glob(os.path.join(src, "models", "*", "bundle.json"))):
        name = os.path.basename(os.path.dirname(path))
        if task is None or load_json(src, f"models/{name}/bundle.json").get("task") == task:
            out.append(name)
    return out


def counts_in_words(counts):
    """{1} -> "one", {1, 2} -> "one or two"."""
    words = [NUMBER_WORDS.get(c, str(c)) for c in sorted(counts)]
    return " or ".join(words)


def subcarrier_counts(src, task):
    return {len(mask_subcarriers(src, b)) for b in bundles(src, task)}


@functools.lru_cache(maxsize=None)
def load_yaml(path):
    """A GRC block or flowgraph file (both YAML), read once per run."""
    import yaml
    return yaml.load(open(path, encoding="utf-8"), Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


def grc_default(src, block, param):
    d = load_yaml(os.path.join(src, "grc", block + ".block.yml"))
    for p in d.get("parameters", []):
        if p.get("id") == param:
            return str(p.get("default"))
    raise LookupError(f"grc/{block}.block.yml: no parameter {param}")


def grc_cp_defaults(src):
    """{block file: default} of every GRC block with a cp_len parameter."""
    out = {}
    for path in sorted(glob.glob(os.path.join(src, "grc", "*.block.yml"))):
        d = load_yaml(path)
        for p in d.get("parameters", []):
            if p.get("id") == "cp_len":
                out[os.path.basename(path)] = str(p.get("default"))
    return out


def example_params(src, name):
    """The Parameter and Variable blocks of examples/<name>.grc: {name: value text}."""
    d = load_yaml(os.path.join(src, "examples", name + ".grc"))
    return {b["name"]: str(b["parameters"].get("value")) for b in d.get("blocks", [])
            if b.get("id") in ("parameter", "variable")}


def time_domain_examples(src):
    """{example: cp_len} of every example flowgraph with a cp_len parameter."""
    out = {}
    for path in sorted(glob.glob(os.path.join(src, "examples", "*.grc"))):
        name = os.path.basename(path)[:-4]
        p = example_params(src, name)
        if "cp_len" in p:
            out[name] = p["cp_len"]
    return out


def cp_examples(src):
    """(the examples whose cp_len is not the frame default, in name order; their cp_len; the
    frame default, which the other time-domain examples keep)."""
    cp = str(int(frame_default(src, "cp_len")))
    td = time_domain_examples(src)
    other = sorted(n for n, v in td.items() if v not in (cp, "-1"))  # -1: the frame's prefix
    return tuple(other) + (" and ".join(sorted({td[n] for n in other})), cp)


def delay_mask_shape(src):
    """(subcarriers, symbols in words) shared by every delay bundle's mask."""
    shapes = {(len(mask_subcarriers(src, b)), len({n for n, _ in mask_pilots(src, b)})) for b in bundles(src, "delay")}
    if len(shapes) != 1:
        return ("differs: " + str(sorted(shapes)), "")
    sub, sym = shapes.pop()
    return (sub, counts_in_words({sym}))


def limits(src):
    """The limits hardening.md and file_formats.md state, in their order."""
    text = open(os.path.join(src, LIMITS_H), encoding="utf-8").read()
    grid = re.search(r"max_grid\s*=\s*1LL\s*<<\s*(\d+)", text)
    n, m = header_default(src, LIMITS_H, "max_symbols"), header_default(src, LIMITS_H, "max_subcarriers")
    return ((n if n == m else f"N {n:g}, M {m:g}"), (2 ** int(grid.group(1)) if grid else "max_grid not found")) + \
        tuple(header_default(src, LIMITS_H, k) for k in ("max_targets", "max_paths", "max_clutter_paths", "max_classes"))


def body_limits(src):
    """The micro-motion limits class_libraries.md states, in its order."""
    get = lambda k: header_default(src, LIMITS_H, k)
    rotors = {get("max_rotors"), get("max_blades"), get("max_wheels")}
    rims = {get("max_rim_points"), get("max_spokes")}
    return (rotors.pop() if len(rotors) == 1 else "differ", rims.pop() if len(rims) == 1 else "differ",
            get("max_scatterers"), get("max_harmonics"))


def example_flags(src):
    """"parameters" when the parameters column of examples/README.md's table names each
    flowgraph's command-line options (its Parameter blocks): all of them for a plain list,
    options it has after "plus" or "and" and options it lacks after "without" for a row that
    reads "as <another row> ..."; else what differs."""
    text = open(os.path.join(src, "examples", "README.md"), encoding="utf-8").read()
    wrong = []
    for row in re.findall(r"^\| `(sems_\w+)\.grc` \|.*\| ([^|]*) \|$", text, re.M):
        name, cell = row
        grc = os.path.join(src, "examples", name + ".grc")
        if not os.path.isfile(grc):
            wrong.append(f"{name}: no such flowgraph")
            continue
        have = {"--" + b["name"].replace("_", "-") for b in load_yaml(grc).get("blocks", []) if b.get("id") == "parameter"}
        if cell.strip().startswith("as "):
            ok_part, _, without = cell.partition("without")
            missing = set(re.findall(r"`(--[\w-]+)`", ok_part)) - have
            extra = set(re.findall(r"`(--[\w-]+)`", without)) & have
            if missing or extra:
                wrong.append(f"{name}: {sorted(missing)} not options, {sorted(extra)} options")
        else:
            stated = set(re.findall(r"`(--[\w-]+)`", cell))
            if stated != have and not (cell.strip() == "none" and not have):
                wrong.append(f"{name}: states {sorted(stated)}, has {sorted(have)}")
    return "parameters" if not wrong else "parameters, but " + "; ".join(wrong)


def paper_class(src, name):
    """(range, speed, micro-Doppler rate and displacement) of a class of models/classes/paper.json,
    the copy of the built-in table: intervals as (low, high), no micro-motion as ()."""
    c = next(c for c in load_json(src, "models/classes/paper.json")["classes"] if c["name"] == name)
    mm = c.get("micro_motion")
    return tuple(c["range_m"]) + tuple(c["speed_mps"]) + ((tuple(mm["rate_hz"]) + (mm["amplitude_m"],)) if mm else ())


def guard_count(frame):
    n = 0
    for g in frame.get("guard_subcarriers", []):
        n += (g[1] - g[0] + 1) if isinstance(g, list) else 1
    return n


def preset(src, name):
    return load_json(src, f"models/frames/{name}.json")


def sh_default(src, script, var):
    m = re.search(r"^%s=(\S+)" % re.escape(var), open(os.path.join(src, script), encoding="utf-8").read(), re.M)
    if not m:
        raise LookupError(f"{script}: no {var}=")
    return m.group(1).strip("\"'")


def py_argparse_default(src, script, flag):
    m = re.search(r"add_argument\(\"%s\"[^)]*default=([^,)]+)" % re.escape(flag),
                  open(os.path.join(src, script), encoding="utf-8").read())
    if not m:
        raise LookupError(f"{script}: no default for {flag}")
    return m.group(1)


def radio(src, name):
    return load_json(src, f"examples/radios/{name}.json")


def radio_row(r):
    """The values the radio table of radio_front_end.md states, in its order."""
    pn, iq, cv = r["phase_noise"], r["iq_imbalance"], r["converter"]
    row = (pn["dbc_hz"], pn["offset_hz"] / 1e3, iq["gain_db"], iq["phase_deg"], r["dc_offset_db"],
           cv["enob"], cv["full_scale_over_rms"])
    if "leakage" in r:
        return (r["leakage"]["power_over_echo_db"], r["oscillator"]) + row
    return (r["oscillator"], pn["dbc_hz"], pn["offset_hz"] / 1e3, r["cfo_hz"] / 1e3, r["sfo_ppm"]) + row[2:]


def presets_with_library(src, library):
    return tuple(sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(src, "models", "frames", "*.json"))
                        if preset(src, os.path.basename(p)[:-5]).get("classes") == library and
                        not os.path.basename(p).startswith("paper")))


def library_count(src, folder):
    return NUMBER_WORDS[len(glob.glob(os.path.join(src, "models", folder, "*.json")))].capitalize()


def other_library_presets(src):
    """How many presets have a library of their own (not paper's, not kinematic)."""
    names = [os.path.basename(p)[:-5] for p in glob.glob(os.path.join(src, "models", "frames", "*.json"))]
    return NUMBER_WORDS[sum(1 for n in names if preset(src, n).get("classes") not in ("paper", "kinematic"))]


def no_bundle_has(src, key, task="classify"):
    """'' when no bundle of the task has decoder.settings[key], else the bundles that have it."""
    have = [b for b in bundles(src, task) if key in load_json(src, f"models/{b}/bundle.json")["decoder"]["settings"]]
    return "" if not have else "present in " + ", ".join(have)


def _fs(src, name):
    return frame_default(src, name)


def _index_m(src):
    """One delay index in metres: c/(2B)."""
    return C_MPS / (2 * _fs(src, "bandwidth_hz"))


# (page, pattern, truth, what): the pattern's groups, read from the page, must equal what
# truth(src) computes from the shipped files (a tuple for several groups; numbers compare as
# numbers, "2 560" = 2560). A space in a pattern matches any run of white space, line breaks
# included. Every pattern must match at least once: a page reworded drops its statement from
# the check, so the entry is updated with it. A statement of a page in FACTS_PENDING that
# disagrees is reported as skipped.
FACTS = [
    # the frame's defaults (include/gnuradio/sems/core/frame/frame_settings.h)
    ("docs/design.md", r"\| `N` symbols per frame \| (\d+) \|", lambda s: _fs(s, "n_symbols"), "N"),
    ("docs/design.md", r"\| `M` subcarriers \| (\d+) \|", lambda s: _fs(s, "n_subcarriers"), "M"),
    ("docs/design.md", r"\| bandwidth `B` \| (\d+) MHz \|", lambda s: _fs(s, "bandwidth_hz") / 1e6, "B in MHz"),
    ("docs/design.md", r"\| carrier `f_c` \| (\d+) GHz \|", lambda s: _fs(s, "carrier_hz") / 1e9, "f_c in GHz"),
    ("docs/design.md", r"\| symbol interval `T` \| (\d+) ms \|", lambda s: _fs(s, "symbol_interval_s") * 1e3, "T in ms"),
    ("docs/design.md", r"\| cyclic prefix \| (\d+) samples \|", lambda s: _fs(s, "cp_len"), "the cyclic prefix"),
    ("docs/design.md", r"\| pilots `N_p` \| (\d+) \|", lambda s: header_default(s, TRAINER_H, "n_pilots"), "N_p"),
    ("docs/design.md", r"At 30 MHz a prefix of (\d+) samples covers (\d+) m",
     lambda s: (_fs(s, "cp_len"), _fs(s, "cp_len") * _index_m(s)), "the default prefix and its range"),
    ("docs/design.md", r"one index is [\d.]+ ns, or (\d+) m of range", _index_m, "one delay index in m"),
    ("README.md", r"One delay index is (\d+) m of range", _index_m, "one delay index in m"),
    ("docs/guides/install.md", r"`frame_settings::cp_len` \((\d+) samples\)", lambda s: _fs(s, "cp_len"), "the default prefix"),
    ("docs/guides/install.md", r"\((\d+) samples = (\d+) m at 30 MHz",
     lambda s: (_fs(s, "cp_len"), _fs(s, "cp_len") * _index_m(s)), "the default prefix and its range"),
    ("docs/reference/time_domain.md", r"The default CP of (\d+) samples covers (\d+) m",
     lambda s: (_fs(s, "cp_len"), _fs(s, "cp_len") * _index_m(s)), "the default prefix and its range"),
    ("docs/reference/time_domain.md", r"takes its prefix from the frame: (\d+) for the default frame", lambda s: _fs(s, "cp_len"), "the default prefix"),
    ("docs/guides/radio_and_files.md", r"\((\d+) MS/s by default\), symbols of M \+ CP samples \(M = (\d+)\)",
     lambda s: (_fs(s, "bandwidth_hz") / 1e6, _fs(s, "n_subcarriers")), "B and M"),
    ("docs/guides/radio_and_files.md", r"the frame's `T`, (\d+) ms by default", lambda s: _fs(s, "symbol_interval_s") * 1e3, "T in ms"),
    # every time-domain block's GRC default prefix is its Frame's (-1), the default frame's in C++
    ("docs/guides/install.md", r"in GRC of its \*Frame\*\s+\((\d+) samples for `paper`\)",
     lambda s: (_fs(s, "cp_len") if set(grc_cp_defaults(s).values()) == {"-1"} else
                "GRC cp_len defaults " + str(grc_cp_defaults(s))), "every GRC block's cp_len default"),
    # the examples' prefixes (examples/*.grc)
    ("docs/guides/install.md", r"`(sems_\w+)` and `(sems_\w+)` set `cp_len` (\d+); the other time-domain examples keep (\d+)",
     cp_examples, "the time-domain examples whose cp_len is not the default, and the others'"),
    ("docs/reference/time_domain.md", r"So `(sems_\w+)`, the time-domain example on the class table's random scenes, and\s+"
     r"`(sems_\w+)`, .*? set \*\*CP = (\d+)\*\*.*?The other time-domain examples keep (\d+)", cp_examples,
     "the time-domain examples whose cp_len is not the default, and the others'"),
    ("docs/reference/time_domain.md", r"\(L = (\d[\d ]*): 3001 samples dropped",
     lambda s: _fs(s, "n_symbols") * (_fs(s, "n_subcarriers") + (lambda cp: cp if cp >= 0 else _fs(s, "cp_len"))(
         float(example_params(s, "sems_replay_sync_td")["cp_len"]))),
     "L = N·(M + CP) of sems_replay_sync_td"),
    # the shipped masks (models/*/mask.json)
    ("docs/reference/time_domain.md", r"the shipped classifier mask \((\d+) pilots, all on subcarrier (\d+)\)",
     lambda s: (len(mask_pilots(s, "classifier")),) + tuple(mask_subcarriers(s, "classifier")), "models/classifier's pilots"),
    ("docs/reference/time_domain.md", r"every shipped classifier's mask \(([a-z ]+) subcarriers?\)",
     lambda s: counts_in_words(subcarrier_counts(s, "classify")), "the classifiers' subcarrier counts"),
    ("docs/reference/time_domain.md", r"the delay masks \((\d+) subcarriers each\)",
     lambda s: counts_in_words(subcarrier_counts(s, "delay")) if len(subcarrier_counts(s, "delay")) > 1
     else next(iter(subcarrier_counts(s, "delay"))), "the delay masks' subcarrier counts"),
    ("docs/reference/time_domain.md", r"\(`models/classifier_sdr_2g4`\) has its (\d+) pilots on ([a-z]+) subcarrier",
     lambda s: (len(mask_pilots(s, "classifier_sdr_2g4")), counts_in_words({len(mask_subcarriers(s, "classifier_sdr_2g4"))})),
     "models/classifier_sdr_2g4's pilots"),
    ("docs/guides/radio_and_files.md", r"\*\*Delay bundles\*\* \(pilots on (\d+) subcarriers of ([a-z]+) symbol\)",
     delay_mask_shape, "the delay masks"),
    ("docs/guides/radio_and_files.md", r"every shipped classifier puts its pilots on ([a-z ]+) subcarriers",
     lambda s: counts_in_words(subcarrier_counts(s, "classify")), "the classifiers' subcarrier counts"),
    ("docs/guides/radio_front_end.md", r"every shipped classifier puts its pilots on ([a-z ]+) subcarriers",
     lambda s: counts_in_words(subcarrier_counts(s, "classify")), "the classifiers' subcarrier counts"),
    # the shipped bundles and presets
    ("docs/reference/frame_files.md", r"Every shipped bundle but `(\w+)` uses it",
     lambda s: " ".join(b for b in bundles(s) if load_json(s, f"models/{b}/bundle.json")["frame"] !=
                        dict(preset(s, "paper")["frame"])), "the bundles not on the paper's frame"),
    ("docs/reference/frame_files.md", r"(\w+) presets ship in `models/frames/`", lambda s: library_count(s, "frames"),
     "the presets in models/frames"),
    ("docs/reference/time_domain.md", r"pilots on all (\d+) used subcarriers",
     lambda s: preset(s, "sdr_2g4_20mhz")["frame"]["n_subcarriers"] - guard_count(preset(s, "sdr_2g4_20mhz")["frame"]),
     "the sdr_2g4_20mhz preset's used subcarriers"),
    ("docs/reference/class_libraries.md", r"(\w+) libraries ship", lambda s: library_count(s, "classes"),
     "the libraries in models/classes"),
    ("docs/reference/class_libraries.md", r"the kinematic one is also the library of the `(\w+)` and `(\w+)` presets\), "
     r"and one for each of the other (\w+)",
     lambda s: presets_with_library(s, "kinematic") + (other_library_presets(s),), "the presets' class libraries"),
    # the radios and examples of the radio guide
    ("docs/guides/radio_front_end.md", r"\| `sdr_monostatic\.json` \| leakage (\d+) dB over the echo, (\w+) oscillator "
     r"(−?\d+) dBc/Hz at (\d+) kHz, IQ ([\d.]+) dB / (\d+)°, DC (−?\d+) dBc, (\d+) bits at (\d+)× rms \|",
     lambda s: radio_row(radio(s, "sdr_monostatic")), "examples/radios/sdr_monostatic.json"),
    ("docs/guides/radio_front_end.md", r"\| `sdr_bistatic\.json` \| (\w+) oscillators (−?\d+) dBc/Hz at (\d+) kHz, "
     r"CFO (\d+) kHz, SFO (\d+) ppm, IQ ([\d.]+) dB / (\d+)°, DC (−?\d+) dBc, (\d+) bits at (\d+)× rms \|",
     lambda s: radio_row(radio(s, "sdr_bistatic")), "examples/radios/sdr_bistatic.json"),
    ("docs/guides/radio_front_end.md", r"\(`--latency`, default (\d[\d ]*) samples",
     lambda s: example_params(s, "sems_radio_monostatic")["latency"], "sems_radio_monostatic's latency"),
    ("docs/guides/radio_front_end.md", r"The converter's full scale is (\d+)× the rms \(`--full-scale`\)",
     lambda s: example_params(s, "sems_radio_monostatic")["full_scale"], "sems_radio_monostatic's full scale"),
    ("docs/guides/radio_front_end.md", r"the radio file's (\d+)× gives a delay MAE",
     lambda s: radio(s, "sdr_monostatic")["converter"]["full_scale_over_rms"], "sdr_monostatic.json's full scale"),
    ("examples/README.md", r"\| flowgraph \| what it shows \| kind \| (parameters) \|", example_flags,
     "each flowgraph's command-line options"),
    # block defaults (grc/*.block.yml)
    ("docs/reference/time_domain.md", r"default threshold `F·L·ρ > (\d+)`", lambda s: grc_default(s, "sems_frame_sync", "threshold"),
     "frame_sync's threshold"),
    ("docs/reference/time_domain.md", r"with the default (\d+) frames per search", lambda s: grc_default(s, "sems_frame_sync", "search_frames"),
     "frame_sync's frames per search"),
    ("docs/reference/sdr_receiver.md", r"the default threshold (\d+) gives", lambda s: grc_default(s, "sems_frame_sync", "threshold"),
     "frame_sync's threshold"),
    ("docs/reference/sdr_receiver.md", r"\(default one frame, (\d[\d ]*)\), with exponential forgetting λ across windows "
     r"\(default ([\d.]+):", lambda s: (grc_default(s, "sems_leakage_canceller", "window"),
                                       grc_default(s, "sems_leakage_canceller", "forgetting")), "leakage_canceller's window and λ"),
    ("docs/guides/grc.md", r"`frames \* (\d+)` for the default N = (\d+)",
     lambda s: (_fs(s, "n_symbols") if grc_default(s, "sems_pilot_mapper", "frame") == "paper" else
                "the mapper's default Frame " + grc_default(s, "sems_pilot_mapper", "frame"),) * 2, "the pilot mapper's N"),
    # the paper's class table (models/classes/paper.json, a copy of the built-in one)
    ("docs/design.md", r"\| pedestrian \| (\d+)–(\d+) \| (\d+)–(\d+) \| (\d+)–(\d+) \| ([\d.]+) m \|",
     lambda s: paper_class(s, "pedestrian"), "the paper's pedestrian"),
    ("docs/design.md", r"\| drone \| (\d+)–(\d+) \| (\d+)–(\d+) \| (\d+)–(\d+) \| ([\d.]+) m \|",
     lambda s: paper_class(s, "drone"), "the paper's drone"),
    ("docs/design.md", r"\| car \| (\d+)–(\d+) \| (\d+)–(\d+) \| none \| — \|", lambda s: paper_class(s, "car"), "the paper's car"),
    ("docs/reference/file_formats.md", r"\| pedestrian \| (\d+)–(\d+) \| (\d+)–(\d+) \| (\d+)–(\d+) \| ([\d.]+) \(\w+ \w+\) \|",
     lambda s: paper_class(s, "pedestrian"), "the paper's pedestrian"),
    ("docs/reference/file_formats.md", r"\| drone \| (\d+)–(\d+) \| (\d+)–(\d+) \| (\d+)–(\d+) \| ([\d.]+) \(\w+ \w+\) \|",
     lambda s: paper_class(s, "drone"), "the paper's drone"),
    ("docs/reference/file_formats.md", r"\| car \| (\d+)–(\d+) \| (\d+)–(\d+) \| none \| — \|", lambda s: paper_class(s, "car"), "the paper's car"),
    # the scene formats' defaults
    ("docs/reference/micro_motion.md", r"`rotors` \((\d+)\), `blades` \((\d+)\),.*?`body_power` \(([\d.]+)\) \|",
     lambda s: tuple(struct_default(s, MOTION_H, "rotor_motion", k) for k in ("rotors", "blades", "body_power")),
     "the rotor model's defaults"),
    ("docs/reference/micro_motion.md", r"`wheels` \((\d+)\), `wheel_radius_m` \(required\), `rim_points` \((\d+)\), "
     r"`spokes` \((\d+)\), `body_power` \(([\d.]+)\), `wheelbase_m` \(([\d.]+)\), `track_m` \(([\d.]+)\)",
     lambda s: tuple(struct_default(s, MOTION_H, "wheels_motion", k)
                     for k in ("wheels", "rim_points", "spokes", "body_power", "wheelbase_m", "track_m")),
     "the wheels model's defaults"),
    ("docs/reference/link_budget.md", r"\| `tx_power_dbm` \| dBm \| (\d+) \|.*?\| `noise_figure_db` \| dB \| (\d+) \|.*?"
     r"\| `noise_temperature_k` \| K \| (\d+) \|",
     lambda s: tuple(header_default(s, LINK_BUDGET_H, k) for k in ("tx_power_dbm", "noise_figure_db", "noise_temperature_k")),
     "the link budget's defaults"),
    # the trainer's defaults (include/gnuradio/sems/learning/training/trainer.h)
    ("docs/guides/training.md", r"\(default (\d[\d ]*), the paper's budget\)", lambda s: header_default(s, TRAINER_H, "frames"),
     "--frames"),
    ("docs/guides/training.md", r"\(defaults (\d+) and (\d+)\)",
     lambda s: (header_default(s, TRAINER_H, "epochs"), header_default(s, TRAINER_H, "decoder_epochs")), "--epochs, --decoder-epochs"),
    ("docs/guides/training.md", r"`--mask-settle-epochs` epochs \(default (\d+)\)",
     lambda s: header_default(s, TRAINER_H, "mask_settle_epochs"), "--mask-settle-epochs"),
    ("docs/guides/training.md", r"the pilot budget \(default (\d+)\)", lambda s: header_default(s, TRAINER_H, "n_pilots"), "--pilots"),
    ("docs/guides/training.md", r"`--pilot-power-floor f` \(default ([\d.]+)\)",
     lambda s: header_default(s, TRAINER_H, "pilot_power_floor"), "--pilot-power-floor"),
    # the readers' limits (include/gnuradio/sems/core/common/limits.h)
    ("docs/reference/hardening.md", r"N, M <= (\d+), N\*M <= (\d+), targets <= (\d+), paths per target <= (\d+), "
     r"clutter paths <= (\d+), classes <= (\d+)", limits, "limits.h"),
    ("docs/reference/file_formats.md", r"N, M <= (\d+), N\*M <= (\d+), targets <= (\d+), paths per target <= (\d+), "
     r"clutter paths <= (\d+), classes <= (\d+)", limits, "limits.h"),
    ("docs/reference/arrays.md", r"a count outside \[1, (\d+)\] \(`limits::max_array_elements`\)",
     lambda s: header_default(s, LIMITS_H, "max_array_elements"), "limits.h"),
    ("docs/reference/class_libraries.md", r"\((\d+) rotors or blades or wheels, (\d+) rim points or spokes, (\d+) scatterers, "
     r"(\d+) harmonics\)", body_limits, "limits.h"),
    # the demo and its test
    ("README.md", r"The demo streams (\d[\d ]*) random-scene frames per SNR", lambda s: sh_default(s, "scripts/demo.sh", "frames"),
     "scripts/demo.sh's frames"),
    ("docs/reference/sinks.md", r"`examples/run_example.py --test` with (\d+) frames",
     lambda s: py_argparse_default(s, "examples/run_example.py", "--frames"), "run_example.py --test's frames"),
]
FACTS_PENDING = set()  # pages another change rewrites: their statements are reported, not failed


def same_value(stated, true):
    """A stated group against the true value: numbers as numbers ("2 560" = 2560.0), text as text."""
    stated = stated.replace("−", "-")
    try:
        a = float(re.sub(r"[ \u2009\u202f]", "", stated))
        b = float(true)
        return abs(a - b) <= 1e-9 * max(1.0, abs(b))
    except (TypeError, ValueError):
        return stated == str(true)


def fact_pattern(pattern):
    """A FACTS pattern with each space matching any run of white space (line breaks included)."""
    return re.compile(pattern.replace(" ", r"\s+"), re.S)


def check_facts(src, problems, skipped, facts=None, pending=None):
    facts = FACTS if facts is None else facts
    pending = FACTS_PENDING if pending is None else pending
    for page, pattern, truth, what in facts:
        bucket = skipped if page in pending else problems
        path = os.path.join(src, page)
        if not os.path.isfile(path):
            bucket.append(f"{page}: no such page (FACTS entry for {what})")
            continue
        text = open(path, encoding="utf-8").read()
        matches = list(fact_pattern(pattern).finditer(text))
        if not matches:
            bucket.append(f"{page}: the statement of {what} is gone (pattern {pattern!r}): update FACTS in "
                          "docs/check_docs.py with the new wording")
            continue
        try:
            true = truth(src)
        except (OSError, LookupError, KeyError, ValueError) as e:
            problems.append(f"{page}: cannot compute {what} from the files: {e}")
            continue
        true = true if isinstance(true, tuple) else (true,)
        for m in matches:
            stated = m.groups()
            line = text.count("\n", 0, m.start()) + 1
            if len(stated) != len(true) or not all(same_value(a, b) for a, b in zip(stated, true)):
                shown = ", ".join(f"{b:g}" if isinstance(b, float) else str(b) for b in true)
                bucket.append(f"{page}:{line}: states {what} as {', '.join(stated)}; the files say {shown}")
    return len(facts)


# ---- snippets: every Python or shell block of the pages runs in CTest or says it is an excerpt -

EXCERPT = re.compile(r"^<!-- excerpt(?::[^>]*)? -->$")
SNIPPET_PAGES_SKIPPED = ("docs/reference/blocks/",)  # generated pages with their own runnable examples (block_reference)
SNIPPETS_PENDING = {"docs/RESULTS.md"}  # and docs/results/*.md: their owner marks them; reported, not failed
# Runnable Python blocks: (page, how the block's first line starts) -> what it shows. A page's
# runnable blocks run in page order as one script, with /usr/bin/python3 on the staged package,
# from a folder where the repository's top-level folders and build/ (the build tree) resolve.
RUNNABLE = {
    ("docs/reference/sinks.md", "import os"): "both sinks in a flowgraph, 64 frames",
    ("docs/guides/training.md", "import numpy as np"): "bundle_decoder on an array",
    ("docs/guides/radio_front_end.md", "from gnuradio import sems"): "radio_front_end from a radio file and keywords",
    ("docs/guides/radio_front_end.md", "clip = sems.converter_full_scale("): "the canceller told the converter's full scale",
}
PY_FENCES = ("python", "py", "python3", "pycon")
SH_FENCES = ("sh", "bash", "shell", "console", "shell-session", "zsh")
PY_LINE = re.compile(r"^(?:from\s+[\w.]+\s+import\b|import\s+[\w.]+|\w+(?:\s*,\s*\w+)*\s*=\s*(?:sems|np|numpy|gr|pmt|os)\."
                     r"|print\(|tb\.)")
SH_FIRST = re.compile(r"^(?:bash|sh|sudo|cmake|ctest|make|git|grcc|gnuradio-companion|export|cd|for|while|if|apt-get|apt|"
                      r"python3|/usr/bin/python3|mkdir|cp|rm|ldconfig|unshare|xargs|nice|time|env|wait|g\+\+|gcc|"
                      r"clang\+\+|sems_\w+|(?:\.\.?/)*(?:build[\w-]*|scripts|apps|examples|tmp|usr|opt)/\S*|/tmp/\S*)$")
LIST_ITEM = re.compile(r"^(\s*)(?:[-*+]|\d+[.)])\s+")


def code_blocks(text):
    """(first line number, fence info, body lines, marked excerpt) of every fenced or indented
    code block of a Markdown text. An indented block starts after a blank line (or an HTML
    comment line) at four columns past the content of the list item it sits in."""
    lines = text.split("\n")
    blocks, levels, list_indent, i = [], [], 0, 0
    while i < len(lines):
        line = lines[i]
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        prev = lines[i - 1].strip() if i else ""
        if stripped.startswith("```"):
            info = stripped[3:].strip().split()
            j = i + 1
            while j < len(lines) and not lines[j].lstrip().startswith("```"):
                j += 1
            body = [l[indent:] if not l[:indent].strip() else l.lstrip() for l in lines[i + 1:j]]
            blocks.append((i + 1, info[0].lower() if info else "", body, excerpt_marked(lines, i)))
            i = j + 1
            continue
        if stripped and indent >= list_indent + 4 and (not prev or prev.startswith("<!--")):
            start, j = indent, i
            while j < len(lines) and (not lines[j].strip() or len(lines[j]) - len(lines[j].lstrip()) >= start):
                j += 1
            while j > i and not lines[j - 1].strip():
                j -= 1
            blocks.append((i + 1, "", [l[start:] for l in lines[i:j]], excerpt_marked(lines, i)))
            i = j
            continue
        item = LIST_ITEM.match(line)
        if item:  # a list item: its content starts after the marker
            levels = [c for c in levels if c <= indent] + [len(item.group(0))]
        elif stripped and not prev:  # a paragraph after a blank line belongs to the items it is indented under
            levels = [c for c in levels if c <= indent]
        list_indent = levels[-1] if levels else 0
        i += 1
    return blocks


def excerpt_marked(lines, i):
    """Whether the last non-blank line before line i is the excerpt marker."""
    j = i - 1
    while j >= 0 and not lines[j].strip():
        j -= 1
    return j >= 0 and bool(EXCERPT.match(lines[j].strip()))


def block_language(info, body):
    """"python", "sh" or None (JSON, C++, output, formulas) for a code block."""
    if info in PY_FENCES:
        return "python"
    if info in SH_FENCES:
        return "sh"
    if info:
        return None
    lines = [l.strip() for l in body if l.strip() and not l.strip().startswith("#")]
    if not lines:
        return None
    if any(PY_LINE.match(l) for l in lines):
        return "python"
    first = lines[0].split()[0]
    return "sh" if SH_FIRST.match(first) or re.match(r"^[A-Z_][A-Z0-9_]*=", first) else None


def snippet_pages(src):
    """README.md and the pages under docs/ (outside docs/results/notes/), as the checks read them."""
    return [d for d in documents(src) if (d == "README.md" or d.startswith("docs/"))
            and not d.startswith(SNIPPET_PAGES_SKIPPED)]


def collect_snippets(src, problems, skipped, runnable=None):
    """{page: [runnable Python blocks in page order]}, after checking every block is one or
    the other; and the number of Python and shell blocks seen."""
    runnable = RUNNABLE if runnable is None else runnable
    used, scripts, seen = set(), {}, 0
    for page in snippet_pages(src):
        pending = page in SNIPPETS_PENDING or (page.startswith("docs/results/") and not page.startswith(NOTES))
        for n, info, body, marked in code_blocks(open(os.path.join(src, page), encoding="utf-8").read()):
            lang = block_language(info, body)
            if lang is None:
                continue
            seen += 1
            first = next((l.strip() for l in body if l.strip()), "")
            keys = [k for k in runnable if k[0] == page and first.startswith(k[1])]
            where = f"{page}:{n}"
            if marked and keys:
                problems.append(f"{where}: a {lang} block both marked <!-- excerpt --> and listed in RUNNABLE")
            elif keys:
                used.add(keys[0])
                if lang != "python":
                    problems.append(f"{where}: a {lang} block listed in RUNNABLE: only Python blocks run; mark it <!-- excerpt -->")
                else:
                    scripts.setdefault(page, []).append((n, "\n".join(body)))
            elif not marked:
                what = (f"{where}: a {lang} block that neither runs nor is marked: put <!-- excerpt --> on the line "
                        f"before it, or list it in RUNNABLE (docs/check_docs.py) and make it run")
                (skipped if pending else problems).append(what + (" (page of another change)" if pending else ""))
    for key in sorted(set(runnable) - used):
        problems.append(f"{key[0]}: RUNNABLE lists a block starting {key[1]!r}, which the page does not have")
    return scripts, seen


def linked_tree(src, build, where):
    """A folder whose entries link to the repository's top-level entries, and build/ to the
    build tree: the pages' relative paths (examples/radios/..., build/python_pkg) resolve
    there, and nothing a snippet writes lands in the source tree's root."""
    for name in os.listdir(src):
        if name not in ("build", ".git"):
            os.symlink(os.path.join(src, name), os.path.join(where, name))
    if build:
        os.symlink(build, os.path.join(where, "build"))


def run_snippets(src, build, scripts, problems, timeout=300):
    import tempfile
    env = dict(os.environ, SEMS_SOURCE_DIR=src, OMP_NUM_THREADS="1")
    if build:
        env["PYTHONPATH"] = os.path.join(build, "python_pkg") + os.pathsep + env.get("PYTHONPATH", "")
        env["LD_LIBRARY_PATH"] = os.path.join(build, "lib") + os.pathsep + env.get("LD_LIBRARY_PATH", "")
    with tempfile.TemporaryDirectory(prefix="sems_snippets_") as tmp:
        tree = os.path.join(tmp, "tree")
        os.makedirs(tree)
        linked_tree(src, build, tree)
        for page, blocks in sorted(scripts.items()):
            script = os.path.join(tmp, page.replace("/", "_") + ".py")
            with open(script, "w", encoding="utf-8") as f:
                for n, code in blocks:
                    f.write(f"# {page}:{n}\n{code}\n\n")
            try:
                r = subprocess.run(["/usr/bin/python3", script], cwd=tree, env=env, capture_output=True, text=True,
                                   timeout=timeout)
            except subprocess.TimeoutExpired:
                problems.append(f"{page}:{blocks[0][0]}: its runnable Python blocks did not finish in {timeout} s")
                continue
            if r.returncode != 0:
                tail = " | ".join((r.stderr or r.stdout).strip().splitlines()[-3:])
                problems.append(f"{page}:{blocks[0][0]}: its runnable Python blocks fail (exit {r.returncode}): {tail}")


def check_snippets(src, build, problems, skipped):
    scripts, seen = collect_snippets(src, problems, skipped)
    if not build or not os.path.isdir(os.path.join(build, "python_pkg")):
        skipped.append(f"the runnable Python blocks of {', '.join(sorted(scripts))}: no staged package "
                       "(--build with python_pkg), not run")
    else:
        run_snippets(src, build, scripts, problems)
    return seen


def check_selftest_new(src):
    """The facts and snippets checks on the made-up repository; returns the failures."""
    failed = 0

    def expect(check, got, wanted, unwanted=(), count=None):
        nonlocal failed
        text = "\n".join(got)
        for w in wanted:
            if w not in text:
                print(f"selftest {check}: expected '{w}', got:\n{text}")
                failed += 1
        for u in unwanted:
            if u in text:
                print(f"selftest {check}: reported '{u}', which is fine:\n{text}")
                failed += 1
        if count is not None and len(got) != count:
            print(f"selftest {check}: expected {count} reports, got {len(got)}:\n{text}")
            failed += 1

    facts = [("docs/facts.md", r"(\d+) pilots, all on subcarrier (\d+)",
              lambda s: (len(mask_pilots(s, "classifier")),) + tuple(mask_subcarriers(s, "classifier")), "the mask"),
             ("docs/facts.md", r"all on subcarrier (\d+) symbols", lambda s: 17, "a statement since reworded"),
             ("models/README.md", r"(three) other jobs", lambda s: "two", "a pending page's statement")]
    problems, skipped = [], []
    check_facts(src, problems, skipped, facts, {"models/README.md"})
    expect("facts", problems, ["docs/facts.md:6: states the mask as 3, 32; the files say 3, 17",
                               "docs/facts.md: the statement of a statement since reworded is gone"],
           ["docs/facts.md:3"], count=2)
    expect("facts (pending)", skipped, ["models/README.md:8: states a pending page's statement as three"], count=1)

    runnable = {("docs/snip.md", "import sys"): "fails", ("docs/snip.md", "print(len"): "runs after it",
                ("docs/snip.md", "import nothing"): "gone"}
    problems, skipped = [], []
    scripts, seen = collect_snippets(src, problems, skipped, runnable)
    expect("snippets", problems, ["docs/snip.md:8: a sh block that neither runs nor is marked",
                                  "README.md:5: a sh block", "RUNNABLE lists a block starting 'import nothing'"],
           ["docs/snip.md:4", "docs/snip.md:22", "docs/snip.md:26", "json"], count=3)
    if [n for n, _ in scripts.get("docs/snip.md", [])] != [10, 26] or seen != 6:
        print(f"selftest snippets: expected the Python blocks at lines 10 and 26 of 6 blocks (README.md has one), got {scripts}, {seen}")
        failed += 1
    problems = []
    run_snippets(src, None, scripts, problems, timeout=60)
    expect("snippets (run)", problems, ["docs/snip.md:10: its runnable Python blocks fail (exit 3)"], count=1)
    problems = []
    run_snippets(src, None, {"docs/snip.md": scripts.get("docs/snip.md", [])[1:]}, problems, timeout=60)
    expect("snippets (run)", problems, [], count=0)
    return failed


def selftest():
    """Each check finds what it is there to find, on a small made-up repository."""
    import tempfile
    with tempfile.TemporaryDirectory() as src:
        os.makedirs(os.path.join(src, "docs", "results", "notes"))
        os.makedirs(os.path.join(src, "scripts"))
        os.makedirs(os.path.join(src, "lib"))
        with open(os.path.join(src, "scripts", "ok.py"), "w") as f:
            f.write("import argparse\nargparse.ArgumentParser().parse_args()\n")
        with open(os.path.join(src, "scripts", "bad.py"), "w") as f:
            f.write("import argparse\nimport sys\nsys.exit(3)\n")
        with open(os.path.join(src, "scripts", "needs_sems.py"), "w") as f:
            f.write("import argparse\nfrom gnuradio import sems\n")
        with open(os.path.join(src, "docs", "page.md"), "w") as f:
            f.write("# A page\n\n## Two words\n")
        with open(os.path.join(src, "README.md"), "w") as f:
            f.write("See [the page](docs/page.md#two-words) and ![fig](docs/missing.png),\n"
                    "[bad anchor](docs/page.md#three-words), `scripts/gone.sh`.\n"
                    "The bar of issue 12 is not met (Nov 24 2026, run C).\n\n"
                    "    /usr/bin/python3 scripts/ok.py --x\n"
                    "    PYTHONPATH=x nice /usr/bin/python3 scripts/bad.py\n"
                    "    bash scripts/absent.sh\n"
                    "    /usr/bin/python3 scripts/needs_sems.py\n")
        with open(os.path.join(src, "docs", "results", "notes", "old.md"), "w") as f:
            f.write("issue 3 [x](nowhere.md)\n")
        os.makedirs(os.path.join(src, "models"))
        os.makedirs(os.path.join(src, "docs", "results"), exist_ok=True)
        with open(os.path.join(src, "models", "README.md"), "w") as f:
            f.write("# Bundles\n\nAccuracy **61.5 %** at 10 dB, MAE 0.0255, 0.94 × the CRB, 30 000 frames,\n"
                    "GNU Radio 3.10, a 4 096-point FFT, 98.9 %.\n\n    sems_train --lr 0.003 --frames 15 308\n")
        with open(os.path.join(src, "docs", "page.md"), "a") as f:
            f.write("\nThe bundle reaches 61.5 % ([models](../models/README.md)); GNU Radio\n3.10, 4 096 "
                    "samples, 30 000 frames, 0.94 of it, `0.0255`, 98.9 %, and\n\n    --lr 0.003\n")
        with open(os.path.join(src, "docs", "results", "tables.md"), "w") as f:
            f.write("| SemS | 0.0255 |\n")
        with open(os.path.join(src, "docs", "guides.md"), "w") as f:
            f.write("# Guide\n\n15 308 Hz and 0.0255 index\n")
        with open(os.path.join(src, "lib", "a.cc"), "w") as f:
            f.write("// fixed in #27 this session\n#include <x>\n// see docs/gone.md\n"
                    "// CPU time stays steady when other jobs share the cores\n")
        with open(os.path.join(src, "docs", "guides.md"), "a") as f:
            f.write("\nAn earlier run found it, at load ~12.\n")
        with open(os.path.join(src, "docs", "results", "run.log"), "w") as f:
            f.write("[12:00:00] model trained, bundle out/eval/bundles/x\nwrote /work/runs/e8out/x.csv\n")
        with open(os.path.join(src, "docs", "results", "ok.csv"), "w") as f:
            f.write("model\nmodels/classifier\n")
        with open(os.path.join(src, "models", "README.md"), "a") as f:
            f.write("\nTrained while three other jobs shared the cores.\n")
        os.makedirs(os.path.join(src, "models", "classifier"))
        with open(os.path.join(src, "models", "classifier", "mask.json"), "w") as f:
            f.write('{"pilots": [[0, 17], [1, 17], [2, 17]]}')
        with open(os.path.join(src, "docs", "facts.md"), "w") as f:
            f.write("# Facts\n\nThe mask has 3 pilots, all on\nsubcarrier 17.\n\nElsewhere: 3 pilots, all on subcarrier 32.\n")
        with open(os.path.join(src, "docs", "snip.md"), "w") as f:
            f.write("# Snippets\n\n<!-- excerpt -->\n    cmake --build build\n\nThen:\n\n    ctest --test-dir build\n\n"
                    "```python\nimport sys\nsys.exit(3)\n```\n\n```json\n{\"a\": 1}\n```\n\n- an item:\n\n"
                    "  <!-- excerpt -->\n      export X=1\n\nAnd after the list:\n\n    print(len('ok'))\n")
        expect = {
            "links": ["docs/missing.png", "#three-words", "scripts/gone.sh"],
            "commands": ["scripts/bad.py --help: exit status 3", "scripts/absent.sh: no such file",
                         "scripts/needs_sems.py imports gnuradio.sems: the command needs PYTHONPATH"],
            "wording": ["README.md:3: an issue number", "lib/a.cc:1: an issue number (#N)",
                        "lib/a.cc:3: names docs/gone.md", "docs/guides.md:5: run history",
                        "docs/results/run.log:2: a folder of the machine"],
            "numbers": ["docs/page.md:5: 61.5 is also stated by hand in models/README.md:3",
                        "docs/guides.md:3: 0.0255 is also stated by hand in models/README.md:3"],
        }
        failed = check_selftest_new(src)
        global HISTORY_PENDING
        saved_pending, HISTORY_PENDING = HISTORY_PENDING, {"models/README.md"}  # a page being rewritten: reported, not failed
        for check, wanted in expect.items():
            problems, skipped = [], []
            {"links": lambda: check_links(src, problems, skipped),
             "commands": lambda: check_commands(src, None, problems, skipped),
             "wording": lambda: check_wording(src, problems, skipped),
             # models/README.md stands for a hand-written page here (the real one is generated)
             "numbers": lambda: check_numbers(src, problems, skipped, generated=GENERATED - {"models/README.md"})}[check]()
            text = "\n".join(problems)
            for w in wanted:
                if w not in text:
                    print(f"selftest {check}: expected a problem with '{w}', got:\n{text}")
                    failed += 1
            if any("notes" in p for p in problems) or any("ok.py" in p for p in problems) \
                    or any("run.log:1" in p or "ok.csv" in p for p in problems) \
                    or any("two-words" in p for p in problems) or any("lib/a.cc:4" in p for p in problems) \
                    or any(p.startswith("models/README.md") and "run history" in p for p in problems):
                print(f"selftest {check}: reported something that is fine:\n{text}")
                failed += 1
            if check == "links" and len(problems) != 3:
                print(f"selftest links: expected 3 problems, got {len(problems)}:\n{text}")
                failed += 1
            if check == "numbers" and len(problems) != 3:  # 61.5, 0.0255 and 98.9 (allowed elsewhere only)
                print(f"selftest numbers: expected 3 problems, got {len(problems)}:\n{text}")
                failed += 1
        HISTORY_PENDING = saved_pending
        print(f"check_docs selftest: {'failed' if failed else 'passed'}")
        return 1 if failed else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", help="the repository's root")
    ap.add_argument("check", choices=("links", "commands", "wording", "numbers", "facts", "snippets", "selftest"))
    ap.add_argument("--build", help="a build tree, for the built apps and gnuradio.sems")
    a = ap.parse_args()
    src = os.path.abspath(a.source)
    build = os.path.abspath(a.build) if a.build else None
    problems, skipped = [], []
    if a.check == "selftest":
        return selftest()
    if a.check == "links":
        n = check_links(src, problems, skipped)
        what = "links and paths"
    elif a.check == "commands":
        n = check_commands(src, build, problems, skipped)
        what = "commands"
    elif a.check == "numbers":
        n = check_numbers(src, problems, skipped)
        what = "documents"
    elif a.check == "facts":
        n = check_facts(src, problems, skipped)
        what = "statements"
    elif a.check == "snippets":
        n = check_snippets(src, build, problems, skipped)
        what = "Python and shell blocks"
    else:
        n = check_wording(src, problems, skipped)
        what = "files"
    for s in skipped:
        print(f"skipped: {s}")
    for p in problems:
        print(p)
    print(f"check_docs {a.check}: {n} {what} checked, {len(problems)} problems, {len(skipped)} skipped")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
