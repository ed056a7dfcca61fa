#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Python docstrings from the Doxygen comments of the public headers.

The text lives once, in the headers' Doxygen comments. Doxygen turns it into XML at build
time; this script turns the XML into a C++ header of docstrings that the pybind11 bindings
use through GNU Radio 3.10's D(...) macro (as gr_modtool's docstrings/*_pydoc_template.h):

    D(target_channel)          the class gr::sems::target_channel
    D(target_channel, make)    its member make
    D(nn, encoder_settings)    the struct gr::sems::nn::encoder_settings
    D(class_from_name)         the free function gr::sems::class_from_name

Overloads share one docstring (the first overload's, with the others' appended).
Without XML (no doxygen on the build machine) every D(...) is an empty string, so the
bindings always compile.

Usage: doxygen_pydoc.py XML_DIR OUTPUT_HEADER     (XML_DIR may be absent: empty docstrings)
"""
import os
import re
import sys
import textwrap
import xml.etree.ElementTree as ET

NAMESPACE = "gr::sems::"
PY_EXCEPTIONS = {"std::invalid_argument": "ValueError", "std::runtime_error": "RuntimeError",
                 "std::out_of_range": "IndexError"}


def inline_text(el):
    """The text of a description element, Doxygen markup reduced to plain text."""
    if el is None:
        return ""
    parts = []

    def walk(e):
        tag = e.tag
        if tag in ("parameterlist", "simplesect", "xrefsect"):
            return  # rendered separately
        if tag == "verbatim" or tag == "preformatted":
            parts.append("\n\n" + textwrap.indent((e.text or "").strip("\n"), "    ") + "\n\n")
            if e.tail:
                parts.append(e.tail)
            return
        if tag == "linebreak":
            parts.append("\n")
        if tag == "computeroutput":
            parts.append("`")
        if e.text:
            parts.append(e.text)
        for child in e:
            walk(child)
        if tag == "computeroutput":
            parts.append("`")
        if tag == "para":
            parts.append("\n\n")
        if e.tail:
            parts.append(e.tail)

    for child in el:
        walk(child)
    text = "".join(parts)
    paragraphs = [p for p in re.split(r"\n\s*\n", text)]
    out = []
    for p in paragraphs:
        if not p.strip():
            continue
        if p.startswith("    "):  # verbatim block: keep its lines
            out.append(p.rstrip())
        else:
            p = " ".join(p.split())
            if p:
                out.append(p)
    return "\n\n".join(out)


def sections(detailed):
    """Args / Returns / Raises of a detaileddescription."""
    args, returns, raises = [], [], []
    if detailed is None:
        return args, returns, raises
    for plist in detailed.iter("parameterlist"):
        target = raises if plist.get("kind") == "exception" else args
        for item in plist.findall("parameteritem"):
            names = ", ".join("".join(n.itertext()).strip() for n in item.iter("parametername"))
            if target is raises:  # what Python sees (pybind11's exception translation)
                names = PY_EXCEPTIONS.get(names, names)
            target.append((names, inline_text(item.find("parameterdescription"))))
    for sect in detailed.iter("simplesect"):
        if sect.get("kind") == "return":
            returns.append(inline_text(sect))
    return args, returns, raises


def docstring(node):
    brief = inline_text(node.find("briefdescription"))
    detailed = node.find("detaileddescription")
    details = inline_text(detailed)
    args, returns, raises = sections(detailed)
    blocks = [b for b in (brief, details) if b]
    if args:
        blocks.append("Args:\n" + "\n".join(f"    {n}: {d}" for n, d in args))
    if returns:
        blocks.append("Returns:\n" + "\n".join(f"    {r}" for r in returns))
    if raises:
        blocks.append("Raises:\n" + "\n".join(f"    {n}: {d}" for n, d in raises))
    return "\n\n".join(blocks)


def symbol(qualified):
    """gr::sems::nn::encoder_settings::to_json -> __doc_nn_encoder_settings_to_json"""
    if not qualified.startswith(NAMESPACE):
        return None
    name = qualified[len(NAMESPACE):]
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_:]*", name):
        return None
    if "operator" in name or "~" in name:
        return None
    return "__doc_" + name.replace("::", "_")


def collect(xml_dir):
    docs = {}

    def add(sym, text):
        if sym is None or not text:
            return
        if sym in docs:
            if text not in docs[sym]:
                docs[sym] += "\n\n" + text
        else:
            docs[sym] = text

    for fname in sorted(os.listdir(xml_dir)):
        if not fname.endswith(".xml") or fname == "index.xml":
            continue
        root = ET.parse(os.path.join(xml_dir, fname)).getroot()
        for comp in root.iter("compounddef"):
            kind = comp.get("kind")
            cname = (comp.findtext("compoundname") or "").strip()
            if kind in ("class", "struct"):
                add(symbol(cname), docstring(comp))
            if kind not in ("class", "struct", "namespace"):
                continue
            for member in comp.iter("memberdef"):
                if member.get("prot", "public") != "public":
                    continue
                mkind = member.get("kind")
                if mkind not in ("function", "variable", "enum", "typedef"):
                    continue
                qname = (member.findtext("qualifiedname") or "").strip()
                if not qname:
                    qname = cname + "::" + (member.findtext("name") or "")
                add(symbol(qname), docstring(member))
    return docs


def cxx_string(text):
    delim = "pydoc"
    assert ")" + delim + '"' not in text
    return 'R"' + delim + "(" + text + ")" + delim + '"'


PREAMBLE = """// SPDX-License-Identifier: GPL-3.0-or-later
// Generated by docs/doxygen_pydoc.py from the Doxygen XML of the public headers. Do not edit:
// the text lives in include/gnuradio/sems/**.h.
#ifndef INCLUDED_SEMS_PYDOC_H
#define INCLUDED_SEMS_PYDOC_H

#define __SEMS_DOC_EXPAND(x) x
#define __SEMS_DOC_COUNT(_1, _2, _3, _4, COUNT, ...) COUNT
#define __SEMS_DOC_SIZE(...) __SEMS_DOC_EXPAND(__SEMS_DOC_COUNT(__VA_ARGS__, 4, 3, 2, 1))
#define __SEMS_DOC_CAT1(a, b) a##b
#define __SEMS_DOC_CAT2(a, b) __SEMS_DOC_CAT1(a, b)
"""


def main():
    xml_dir, out = sys.argv[1], sys.argv[2]
    have_xml = os.path.isfile(os.path.join(xml_dir, "index.xml"))
    lines = [PREAMBLE]
    if have_xml:
        docs = collect(xml_dir)
        lines.append("#define __SEMS_DOC1(n1) __doc_##n1")
        lines.append("#define __SEMS_DOC2(n1, n2) __doc_##n1##_##n2")
        lines.append("#define __SEMS_DOC3(n1, n2, n3) __doc_##n1##_##n2##_##n3")
        lines.append("#define __SEMS_DOC4(n1, n2, n3, n4) __doc_##n1##_##n2##_##n3##_##n4")
        lines.append("#define D(...) __SEMS_DOC_EXPAND(__SEMS_DOC_CAT2(__SEMS_DOC, __SEMS_DOC_SIZE(__VA_ARGS__))(__VA_ARGS__))")
        lines.append("")
        for sym in sorted(docs):
            lines.append(f"[[maybe_unused]] static const char* {sym} = {cxx_string(docs[sym])};")
    else:
        lines.append("// No Doxygen XML at build time: empty docstrings.")
        lines.append('#define D(...) ""')
    lines.append("\n#endif /* INCLUDED_SEMS_PYDOC_H */\n")
    text = "\n".join(lines)
    old = open(out).read() if os.path.exists(out) else None
    if text != old:  # keep the timestamp when nothing changed (no needless rebuilds)
        os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
        with open(out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
