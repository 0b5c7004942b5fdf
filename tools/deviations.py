#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Deviation log: every static-analysis suppression in lib/, port/ and apps/, with its reason.

In-code suppressions (the forms the project uses):
  code;  // NOLINT(check-a,check-b): reason
  // NOLINTNEXTLINE(check): reason
  // NOLINTBEGIN(check): reason   ...   // NOLINTEND(check)
  // cppcheck-suppress id ; reason
Each must name its checks and give a one-line reason; a suppression without
a reason, or a blanket NOLINT without a check list, is an error (exit 1).

Configuration-level deviations are listed too: checks disabled in .clang-tidy
(reason: the comment line naming the check) and entries of
tools/cppcheck-suppressions.txt (reason: the // comment above the entry).
A configuration entry without a reason is reported as a warning (those files
belong to the lint set-up, not to this script).

Output: certification/deviations.md (deterministic: no line numbers, so an
edit elsewhere in a file does not change the log; each entry quotes its code
line instead).

Usage: tools/deviations.py [--out FILE]
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCOPE = ["lib", "port", "apps"]
EXTS = (".cpp", ".hpp", ".h", ".cc", ".c")


def tracked_files():
    """Paths (relative, '/') that git tracks, or None outside a git work tree.
    Evidence is built from committed files only, so a colleague's untracked
    work in progress does not change it."""
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "-z"], capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return {p for p in out.decode("utf-8", "replace").split("\0") if p}

NOLINT = re.compile(r"//\s*(NOLINTNEXTLINE|NOLINTBEGIN|NOLINTEND|NOLINT)\b(\(([^)]*)\))?(.*)$")
CPPCHECK = re.compile(r"//\s*cppcheck-suppress(?:-file|-begin|-end|-macro)?\s+(\S+?)\s*(?:;\s*(.*))?$")


def rel(p):
    return os.path.relpath(p, ROOT).replace(os.sep, "/")


def reason_of(tail):
    """The reason after ':' (NOLINT forms)."""
    t = tail.strip()
    if t.startswith(":"):
        t = t[1:].strip()
    else:
        return ""
    return t


def code_of(line, start):
    code = line[:start].strip()
    return code


def md(s):
    return s.replace("|", "\\|")


def scan():
    entries, errors = [], []
    tracked = tracked_files()
    for top in SCOPE:
        for dirpath, dirnames, filenames in os.walk(os.path.join(ROOT, top)):
            dirnames.sort()
            for fn in sorted(filenames):
                if not fn.endswith(EXTS):
                    continue
                path = os.path.join(dirpath, fn)
                if tracked is not None and rel(path) not in tracked:
                    continue
                with open(path, encoding="utf-8", errors="replace") as f:
                    lines = f.read().splitlines()
                for i, line in enumerate(lines):
                    m = NOLINT.search(line)
                    if m:
                        kind, checks, tail = m.group(1), (m.group(3) or "").strip(), m.group(4)
                        if kind == "NOLINTEND":
                            continue
                        reason = reason_of(tail)
                        code = code_of(line, m.start())
                        if kind in ("NOLINTNEXTLINE", "NOLINTBEGIN"):
                            nxt = lines[i + 1].strip() if i + 1 < len(lines) else ""
                            code = nxt if kind == "NOLINTNEXTLINE" else "(block) " + nxt
                        where = f"{rel(path)}: {kind}"
                        if not checks:
                            errors.append(f"{where} names no check (blanket suppression): {line.strip()}")
                        if not reason:
                            errors.append(f"{where}({checks}) has no reason (expected '): reason'): {line.strip()}")
                        entries.append(("clang-tidy", rel(path), kind, checks, reason, code))
                        continue
                    m = CPPCHECK.search(line)
                    if m:
                        ident, reason = m.group(1), (m.group(2) or "").strip()
                        nxt = lines[i + 1].strip() if i + 1 < len(lines) else ""
                        code = code_of(line, m.start()) or nxt
                        if not reason:
                            errors.append(f"{rel(path)}: cppcheck-suppress {ident} has no reason (expected '; reason')")
                        entries.append(("cppcheck", rel(path), "cppcheck-suppress", ident, reason, code))
    return entries, errors


def clang_tidy_config():
    path = os.path.join(ROOT, ".clang-tidy")
    out, warnings = [], []
    if not os.path.exists(path):
        return out, ["no .clang-tidy"]
    text = open(path, encoding="utf-8").read()
    reasons = {}
    for line in text.splitlines():
        m = re.match(r"^#\s*-\s*(.+?):\s*(.+)$", line)
        if m:
            for name in m.group(1).split(","):
                reasons[name.strip()] = m.group(2).strip()
    m = re.search(r"^Checks:\s*>?\s*\n((?:\s+.*\n?)*)", text, re.M)
    checks = []
    if m:
        for item in m.group(1).split(","):
            item = item.strip()
            if item.startswith("-"):
                checks.append(item[1:])
    for c in checks:
        r = reasons.get(c, "")
        if not r:
            warnings.append(f".clang-tidy disables {c} without a reason comment")
        out.append((c, r))
    return out, warnings


def cppcheck_config():
    path = os.path.join(ROOT, "tools", "cppcheck-suppressions.txt")
    out, warnings = [], []
    if not os.path.exists(path):
        return out, warnings
    pending = []
    for line in open(path, encoding="utf-8").read().splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("//") or s.startswith("#"):
            pending.append(s.lstrip("/#").strip())
            continue
        reason = pending[-1] if pending else ""  # the comment line directly above the entry
        pending = []
        if not reason:
            warnings.append(f"tools/cppcheck-suppressions.txt: {s} has no reason comment")
        out.append((s, reason))
    return out, warnings


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "certification", "deviations.md"))
    args = ap.parse_args()

    entries, errors = scan()
    tidy, w1 = clang_tidy_config()
    cpc, w2 = cppcheck_config()

    L = ["# Deviation log: static-analysis suppressions", "",
         "Generated by `tools/deviations.py`; do not edit. Scope: lib/, port/ and apps/, the code",
         "that `tools/lint.sh` analyses with zero findings allowed. Each in-code",
         "suppression names its checks and states its reason; the script fails when",
         "one does not. See [static-analysis.md](static-analysis.md) for the rule sets.", ""]
    L.append("## Summary")
    L.append("")
    n_tidy = sum(1 for e in entries if e[0] == "clang-tidy")
    n_cpc = sum(1 for e in entries if e[0] == "cppcheck")
    L.append(f"- in-code clang-tidy suppressions (NOLINT, NOLINTNEXTLINE, NOLINTBEGIN): {n_tidy}")
    L.append(f"- in-code cppcheck suppressions (cppcheck-suppress): {n_cpc}")
    L.append(f"- clang-tidy checks disabled in .clang-tidy: {len(tidy)}")
    L.append(f"- cppcheck suppressions in tools/cppcheck-suppressions.txt: {len(cpc)}")
    L.append(f"- suppressions without a reason: {len(errors)}")
    counts = {}
    for e in entries:
        for c in (x.strip() for x in e[3].split(",")):
            if c:
                counts[c] = counts.get(c, 0) + 1
    L.append("")
    L.append("Suppressed rule, number of in-code suppressions:")
    L.append("")
    L.append("| rule | count |")
    L.append("|---|---|")
    for c in sorted(counts):
        L.append(f"| {c} | {counts[c]} |")
    L.append("")
    L.append("## In-code suppressions")
    L.append("")
    L.append("| file | tool | form | rules | reason | code |")
    L.append("|---|---|---|---|---|---|")
    for tool, path, kind, checks, reason, code in entries:
        c = code if len(code) <= 90 else code[:87] + "..."
        L.append(f"| {path} | {tool} | {kind} | {md(checks)} | {md(reason) or '**none**'} | `{md(c)}` |")
    L.append("")
    L.append("## Disabled in .clang-tidy (project-wide)")
    L.append("")
    L.append("| check | reason (from the comment in .clang-tidy) |")
    L.append("|---|---|")
    for c, r in tidy:
        L.append(f"| {c} | {md(r) if r else '**not stated in .clang-tidy**'} |")
    L.append("")
    L.append("## tools/cppcheck-suppressions.txt (project-wide)")
    L.append("")
    L.append("| suppression | reason |")
    L.append("|---|---|")
    for s, r in cpc:
        L.append(f"| `{md(s)}` | {md(r) if r else '**not stated**'} |")
    L.append("")
    with open(args.out, "w", encoding="utf-8") as f:
        f.write("\n".join(L))

    for w in w1 + w2:
        print(f"deviations: warning: {w}", file=sys.stderr)
    for e in errors:
        print(f"deviations: error: {e}", file=sys.stderr)
    print(f"deviations: {n_tidy} clang-tidy and {n_cpc} cppcheck in-code suppressions, "
          f"{len(tidy)} checks disabled in .clang-tidy, {len(cpc)} cppcheck config suppressions, "
          f"{len(errors)} without a reason")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
