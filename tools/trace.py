#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Traceability: safety requirements <-> tests.

Reads the requirement IDs from certification/requirements.md (headings
"### SR-AREA-NNN: title", followed by a "Kind:" line and a "Source:" line),
and the tests with the IDs they verify:
  - doctest test cases in tests/**/*.cpp: a comment line
        // verifies: SR-ZONE-002, SR-LOGIC-001
    in the comment block directly above the TEST_CASE;
  - CMake tests in every CMakeLists.txt (outside build directories): a line
        # verifies: SR-GEN-001
    in the comment block directly above the add_test(NAME ...).

Writes certification/traceability.md (requirement -> tests, test ->
requirements) and certification/requirements-index.md. Output is
deterministic: sorted, without line numbers or dates.

Exit status: 1 when a requirement has no test, a test names an unknown
requirement, a test names no requirement, a verifies line is malformed, or
a doctest name holds ';' (ctest would split it and run nothing); 0 otherwise.

Usage: tools/trace.py [--out-dir DIR] [--ctest BUILD_DIR]
  --out-dir  write the two files there instead of certification/
  --ctest    also compare with `ctest -N` of BUILD_DIR (warnings only)
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
REQ_FILE = os.path.join(ROOT, "certification", "requirements.md")
ID_RE = re.compile(r"^SR-[A-Z]+-\d{3}$")
REQ_HEAD = re.compile(r"^###\s+(SR-[A-Z]+-\d{3}):\s*(.+?)\s*$")
TEST_CASE = re.compile(r'^\s*(?:TEST_CASE|TEST_CASE_FIXTURE|SCENARIO|TEST_CASE_TEMPLATE)\s*\(\s*(?:\w+\s*,\s*)?"((?:[^"\\]|\\.)*)"')
ADD_TEST = re.compile(r"^\s*add_test\s*\(\s*NAME\s+([^\s)]+)")
CPP_TAG = re.compile(r"^\s*//\s*verifies:\s*(.*)$")
CMAKE_TAG = re.compile(r"^\s*#\s*verifies:\s*(.*)$")
SKIP_DIRS = {".git", "node_modules"}


def tracked_files():
    """Paths (relative, '/') that git tracks, or None outside a git work tree.
    Evidence is built from committed files only, so a colleague's untracked
    work in progress does not change it."""
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "-z"], capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return {p for p in out.decode("utf-8", "replace").split("\0") if p}


def rel(path):
    return os.path.relpath(path, ROOT).replace(os.sep, "/")


def read_requirements():
    reqs = {}  # id -> dict(title, kind, source)
    order = []
    errors = []
    current = None
    with open(REQ_FILE, encoding="utf-8") as f:
        for line in f:
            m = REQ_HEAD.match(line)
            if m:
                rid, title = m.group(1), m.group(2)
                if rid in reqs:
                    errors.append(f"requirements.md: {rid} is defined twice")
                reqs[rid] = {"title": title, "kind": "", "source": ""}
                order.append(rid)
                current = rid
                continue
            if line.startswith("#"):
                current = None
                continue
            if current is not None:
                km = re.match(r"^Kind:\s*([a-z]+)", line)
                if km and not reqs[current]["kind"]:
                    reqs[current]["kind"] = km.group(1)
                sm = re.match(r"^Source:\s*(.+?)\s*$", line)
                if sm and not reqs[current]["source"]:
                    reqs[current]["source"] = sm.group(1).rstrip(".")
    for rid in order:
        if not reqs[rid]["kind"]:
            errors.append(f"requirements.md: {rid} has no 'Kind:' line")
    return reqs, order, errors


def parse_ids(text):
    ids = [t.strip() for t in text.replace(";", ",").split(",") if t.strip()]
    bad = [t for t in ids if not ID_RE.match(t)]
    return ids, bad


LITERAL = re.compile(r'\s*"((?:[^"\\]|\\.)*)"')


def join_literals(text, pos):
    """The test name: adjacent string literals from pos on, concatenated as C++ does."""
    parts = []
    while True:
        m = LITERAL.match(text, pos)
        if not m:
            break
        parts.append(m.group(1))
        pos = m.end()
    name = "".join(parts)
    return bytes(name, "utf-8").decode("unicode_escape") if "\\" in name else name


def tag_above(lines, i, comment_prefix, tag_re):
    """IDs from a verifies line in the comment block directly above line i."""
    j = i - 1
    while j >= 0 and lines[j].lstrip().startswith(comment_prefix):
        m = tag_re.match(lines[j])
        if m:
            return m.group(1), j
        j -= 1
    return None, None


def walk(pattern_ok):
    tracked = tracked_files()
    for dirpath, dirnames, filenames in os.walk(ROOT):
        top = rel(dirpath).split("/")[0]
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not (dirpath == ROOT and d.startswith("build")))
        if top.startswith("build") or top in ("out",):
            continue
        for fn in sorted(filenames):
            path = os.path.join(dirpath, fn)
            if pattern_ok(dirpath, fn) and (tracked is None or rel(path) in tracked):
                yield path


def tagged_ids(lines, i, comment, pattern, where, name, errors):
    """The requirement IDs of the verifies line above lines[i] (None: no such line); malformed IDs go to errors."""
    tag, _ = tag_above(lines, i, comment, pattern)
    if tag is None:
        return None
    ids, bad = parse_ids(tag)
    for b in bad:
        errors.append(f"{where}: test '{name}': malformed requirement ID '{b}'")
    return [x for x in ids if ID_RE.match(x)]


def find_tests():
    tests = []  # dicts: name, file, kind, ids(list) or None
    errors = []
    tests_dir = os.path.join(ROOT, "tests")
    cpp = [p for p in walk(lambda d, f: f.endswith(".cpp") and os.path.abspath(d).startswith(tests_dir))]
    for path in cpp:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.readlines()
        for i, line in enumerate(lines):
            if not line.lstrip().startswith(("TEST_CASE", "SCENARIO")):
                continue
            # The name may start on the next line (clang-format breaks after
            # "TEST_CASE(" when the name does not fit).
            text = "".join(lines[i:i + 4])
            m = TEST_CASE.match(text)
            if not m:
                continue
            name = join_literals(text, m.start(1) - 1)
            ids = tagged_ids(lines, i, "//", CPP_TAG, rel(path), name, errors)
            tests.append({"name": name, "file": rel(path), "kind": "doctest", "ids": ids})
    cmakes = [p for p in walk(lambda d, f: f == "CMakeLists.txt")]
    for path in cmakes:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.readlines()
        for i, line in enumerate(lines):
            m = ADD_TEST.match(line)
            if not m:
                continue
            name = m.group(1)
            ids = tagged_ids(lines, i, "#", CMAKE_TAG, rel(path), name, errors)
            tests.append({"name": name, "file": rel(path), "kind": "ctest", "ids": ids})
    return tests, errors


def check_hazard_tests(tests):
    """Every test named (in backticks) in the hazard table's test column must exist."""
    path = os.path.join(ROOT, "certification", "hazard-analysis.md")
    if not os.path.exists(path):
        return []
    known = {t["name"] for t in tests}
    errs = []
    col = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("|"):
                col = None
                continue
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
            if col is None:
                col = next((i for i, c in enumerate(cells) if c.startswith("test")), -1)
                continue
            if col < 0 or col >= len(cells):
                continue
            for name in re.findall(r"`([^`]+)`", cells[col]):
                if name not in known:
                    errs.append(f"hazard-analysis.md names test '{name}', which does not exist")
    return errs


def md_escape(s):
    return s.replace("|", "\\|")


def ctest_names(build_dir):
    try:
        out = subprocess.run(["ctest", "--test-dir", build_dir, "-N"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"trace: warning: ctest -N in {build_dir} failed: {e}", file=sys.stderr)
        return None
    names = []
    for line in out.splitlines():
        m = re.match(r"^\s*Test\s+#\d+:\s+(.*?)\s*$", line)
        if m:
            names.append(m.group(1))
    return names


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out-dir", default=os.path.join(ROOT, "certification"))
    ap.add_argument("--ctest", metavar="BUILD_DIR")
    args = ap.parse_args()

    reqs, order, errors = read_requirements()
    tests, terrors = find_tests()
    errors += terrors

    by_req = {rid: [] for rid in order}
    unknown = []
    for t in tests:
        for rid in t["ids"] or []:
            if rid in by_req:
                by_req[rid].append(t)
            else:
                unknown.append((t, rid))
    for t, rid in unknown:
        errors.append(f"{t['file']}: test '{t['name']}' names unknown requirement {rid}")
    errors += check_hazard_tests(tests)
    untested = [rid for rid in order if not by_req[rid]]
    for rid in untested:
        errors.append(f"requirement {rid} ({reqs[rid]['title']}) has no test")
    untagged = [t for t in tests if t["ids"] is None]
    empty = [t for t in tests if t["ids"] == []]
    for t in empty:
        errors.append(f"{t['file']}: test '{t['name']}' has an empty verifies line")
    tagged = [t for t in tests if t["ids"]]
    # CMake lists split on ';': doctest_discover_tests registers a test whose
    # name holds ';' as several ctest entries that each run no test case.
    split = [t for t in tests if t["kind"] == "doctest" and ";" in t["name"]]
    for t in untagged:
        errors.append(f"{t['file']}: test '{t['name']}' names no requirement (add a verifies: line above it)")
    for t in split:
        errors.append(f"{t['file']}: test '{t['name']}' holds ';': ctest splits it into entries that run nothing")

    L = []
    L.append("# Traceability: requirements and tests")
    L.append("")
    L.append("Generated by `tools/trace.py` from certification/requirements.md and the")
    L.append("`verifies:` comments above each test; do not edit. `tools/evidence.sh --check`")
    L.append("fails when this file is out of date.")
    L.append("")
    L.append("## Summary")
    L.append("")
    L.append(f"- requirements: {len(order)} ({sum(1 for r in order if reqs[r]['kind'] == 'safety')} safety, "
             f"{sum(1 for r in order if reqs[r]['kind'] != 'safety')} support)")
    L.append(f"- requirements without a test: {len(untested)}" + (" (" + ", ".join(untested) + ")" if untested else ""))
    L.append(f"- tests found: {len(tests)} ({sum(1 for t in tests if t['kind'] == 'doctest')} doctest test cases, "
             f"{sum(1 for t in tests if t['kind'] == 'ctest')} CMake add_test)")
    L.append(f"- tests naming requirements: {len(tagged)}")
    L.append(f"- tests not yet naming a requirement (error): {len(untagged)}")
    L.append(f"- references to unknown requirements: {len(unknown)}")
    L.append(f"- test names that ctest splits at ';' (error, not run by ctest): {len(split)}")
    L.append("")
    L.append("## Requirement -> tests")
    L.append("")
    L.append("| requirement | kind | title | tests |")
    L.append("|---|---|---|---|")
    for rid in order:
        ts = by_req[rid]
        cell = "<br>".join(f"`{md_escape(t['name'])}` ({t['file']})" for t in ts) if ts else "**none**"
        L.append(f"| {rid} | {reqs[rid]['kind']} | {md_escape(reqs[rid]['title'])} | {cell} |")
    L.append("")
    L.append("## Test -> requirements")
    L.append("")
    files = sorted({t["file"] for t in tests})
    for fpath in files:
        ft = [t for t in tests if t["file"] == fpath]
        L.append(f"### {fpath}")
        L.append("")
        L.append("| test | requirements |")
        L.append("|---|---|")
        for t in ft:
            ids = ", ".join(t["ids"]) if t["ids"] else ("**untagged**" if t["ids"] is None else "**empty**")
            L.append(f"| `{md_escape(t['name'])}` | {ids} |")
        L.append("")
    if split:
        L.append("## Test names that ctest splits (warning)")
        L.append("")
        L.append("These doctest names contain ';'. `doctest_discover_tests` passes them through a CMake")
        L.append("list, so ctest registers each as several entries whose filters match no test case:")
        L.append("ctest reports them passed without running them (the doctest binary run directly does")
        L.append("run them). Rename them without ';'.")
        L.append("")
        for t in split:
            L.append(f"- `{md_escape(t['name'])}` ({t['file']})")
        L.append("")
    if untagged:
        L.append("## Untagged tests (warning)")
        L.append("")
        for t in untagged:
            L.append(f"- `{md_escape(t['name'])}` ({t['file']})")
        L.append("")

    I = []
    I.append("# Requirements index")
    I.append("")
    I.append("Generated by `tools/trace.py` from certification/requirements.md; do not edit.")
    I.append("")
    I.append("| ID | kind | title | implemented in | tests |")
    I.append("|---|---|---|---|---|")
    for rid in order:
        r = reqs[rid]
        I.append(f"| {rid} | {r['kind']} | {md_escape(r['title'])} | {md_escape(r['source'])} | {len(by_req[rid])} |")
    I.append("")

    os.makedirs(args.out_dir, exist_ok=True)
    with open(os.path.join(args.out_dir, "traceability.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(L))
    with open(os.path.join(args.out_dir, "requirements-index.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(I))

    if args.ctest:
        names = ctest_names(args.ctest)
        if names is not None:
            known = {t["name"] for t in tests}
            known |= {piece.strip() for t in split for piece in t["name"].split(";")}
            for n in names:
                if n.strip() not in known:
                    print(f"trace: warning: ctest test '{n}' was not found in the sources (no verifies tag possible)",
                          file=sys.stderr)
    for e in errors:  # untagged tests and names with ';' are among them
        print(f"trace: error: {e}", file=sys.stderr)
    print(f"trace: {len(order)} requirements, {len(tests)} tests, {len(tagged)} tagged, {len(untagged)} untagged, "
          f"{len(untested)} requirements without a test, {len(unknown)} unknown references")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
