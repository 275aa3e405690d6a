#!/usr/bin/env python3
"""Layering test (ctest `layering`): the include graph follows STYLE.md.

Reads every `#include <relief/...>`, `#include <support/...>` and `#include "..."` in the C++
files of src/, tests/, fuzz/, bench/ and python/ and checks:
  direction   a file includes its own layer and below, never above (LEVEL below; viewer and
              bench are peers that do not include each other);
  technique   outside src/relief/techniques/<tech>/ only techniques/registry.cpp includes it
              (a technique's tests live in its folder; shared machinery in techniques/common/);
  tests       src/ never includes from tests/ (only *_test.cpp files, which are tests, may use
              tests/support/); quoted includes never climb out of their folder.
Known exceptions are in ALLOWED, one line each with its reason; an entry that no longer matches
anything is an error too, so the list only shrinks. Usage: layering_test.py [REPO_ROOT]
"""
import fnmatch
import os
import re
import sys

# Layers, lowest first. A file may include modules whose level is ≤ its own.
LEVEL = {
    "core": 0,
    "io": 1, "surface": 1, "sphere": 1,
    "techniques": 2,
    # curves/ sits at render level until it is split into techniques/curves, sphere/, render/.
    "render": 3, "gl": 3, "report": 3, "embree": 3, "curves": 3,
    "preview": 3,  # preview/: meshes and the GL mesh preview (render + gl), below cli and viewer
    "bench": 4, "viewer": 4,
    "cli": 5, "python": 5,  # python/: the Python module, a program beside the CLI
    "tests": 6,  # tests/, fuzz/, every *_test.cpp, tests/support/
}
# Pairs at one level that still must not include each other (includer, included).
SEPARATE_PEERS = {("viewer", "bench"), ("bench", "viewer"), ("python", "cli")}
# Folders of techniques/ that hold machinery several rows share, not a technique.
SHARED_TECHNIQUE_FOLDERS = {"common", "safety_common"}
SCANNED = ("src", "tests", "fuzz", "bench", "python")
SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".inl")

# (file pattern, include pattern, reason): fnmatch patterns on repo-relative paths; the include
# is the resolved path (src/relief/..., tests/...).
ALLOWED = []  # empty: every include follows the rules (issue 16); add one only with a reason

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def module_of(path):
    """(module, technique folder or None, is_test) of a repo-relative path."""
    parts = path.split("/")
    is_test = parts[0] in ("tests", "fuzz") or parts[-1].endswith("_test.cpp")
    if parts[0] == "src" and len(parts) > 2 and parts[1] == "relief":
        module = parts[2] if len(parts) > 3 else None
        tech = parts[3] if module == "techniques" and len(parts) > 4 else None
        return module, tech, is_test
    if parts[0] == "bench":
        return "bench", None, False
    if parts[0] == "python":
        return "python", None, False
    return "tests", None, True


def resolve(root, path, kind, name):
    """The repo-relative path an include names, or None for a system/library header."""
    if kind == "<":
        if name.startswith("relief/"):
            return "src/" + name
        if name.startswith("support/"):
            return "tests/" + name
        return None
    target = os.path.normpath(os.path.join(os.path.dirname(path), name))
    return target if os.path.exists(os.path.join(root, target)) or "/" in name else None


def violations_of(root, path, lineno, text, target):
    mod, tech, is_test = module_of(path)
    tmod, ttech, _ = module_of(target)
    found = []
    if mod is None or (mod not in LEVEL):
        found.append(f"direction: '{mod}' has no layer in LEVEL (add it)")
        return found
    if target.startswith("tests/"):
        if not is_test:
            found.append("tests: non-test code includes from tests/")
        elif (not target.startswith("tests/support/") and
              os.path.dirname(target) != os.path.dirname(path)):
            found.append("tests: test helpers live in tests/support/ (<support/...>)")
        return found
    if tmod not in LEVEL:
        found.append(f"direction: included module '{tmod}' has no layer in LEVEL")
        return found
    level = LEVEL["tests"] if is_test else LEVEL[mod]
    if not is_test and (LEVEL[tmod] > level or (mod, tmod) in SEPARATE_PEERS):
        found.append(f"direction: {mod} (level {LEVEL[mod]}) must not include {tmod} "
                     f"(level {LEVEL[tmod]})")
    if ttech is not None and ttech not in SHARED_TECHNIQUE_FOLDERS:
        own = mod == "techniques" and tech == ttech
        if not own and path != "src/relief/techniques/registry.cpp":
            found.append(f"technique: only techniques/{ttech}/ and techniques/registry.cpp "
                         f"include techniques/{ttech}/")
    if text[0] == '"' and os.path.dirname(target) != os.path.dirname(path):
        found.append('tests: a quoted include reaches across folders (use <relief/...> or '
                     '<support/...>)')
    return found


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(__file__), ".."))
    used = [False] * len(ALLOWED)
    errors = []
    for top in SCANNED:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs.sort()
            for name in sorted(files):
                if not name.endswith(SUFFIXES):
                    continue
                path = os.path.relpath(os.path.join(folder, name), root)
                with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
                    lines = f.read().splitlines()
                for lineno, line in enumerate(lines, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = resolve(root, path, m.group(1), m.group(2))
                    if target is None:
                        continue
                    text = f"{m.group(1)}{m.group(2)}{'>' if m.group(1) == '<' else chr(34)}"
                    for rule in violations_of(root, path, lineno, text, target):
                        allowed = [k for k, (fp, ip, _) in enumerate(ALLOWED)
                                   if fnmatch.fnmatch(path, fp) and fnmatch.fnmatch(target, ip)]
                        for k in allowed:
                            used[k] = True
                        if not allowed:
                            errors.append(f"{path}:{lineno}: #include {text}: {rule}")
    for k, (fp, ip, reason) in enumerate(ALLOWED):
        if not used[k]:
            errors.append(f"tests/layering_test.py: allow-list entry ({fp}, {ip}) matches "
                          f"nothing any more: remove it ({reason})")
    for e in errors:
        print(e)
    print(f"layering: {len(errors)} violation(s), {sum(used)} allowed exception(s) in use")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
