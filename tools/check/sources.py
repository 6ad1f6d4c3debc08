#!/usr/bin/env python3
"""Every source file is built: each .cpp of the tree (and each tests/cli/*.sh) is named in the CMakeLists.txt
of the nearest folder above it that has one. The source lists are written out by name (no globs), so a new
file that nobody added to its list would otherwise just not be compiled. Prints one line per file left
out and exits 1 when there is any.

usage: tools/check/sources.py [REPO]
"""
import os
import sys

SKIP = ("build", ".git", "fuzz-artifacts", "data")


def main(argv):
    root = os.path.abspath(argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
    everything = ""  # every CMake file: a board's list names shared board code by its path
    for folder, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if d not in SKIP and not d.startswith(".")]
        for name in names:
            if name == "CMakeLists.txt" or name.endswith(".cmake"):
                with open(os.path.join(folder, name)) as f:
                    everything += f.read()
    missing = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIP and not d.startswith("."))
        for name in sorted(names):
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, root)
            if not (name.endswith(".cpp") or (rel.startswith("tests/cli/") and name.endswith(".sh"))):
                continue
            lists = folder
            while not os.path.exists(os.path.join(lists, "CMakeLists.txt")) and lists != root:
                lists = os.path.dirname(lists)
            with open(os.path.join(lists, "CMakeLists.txt")) as f:
                text = f.read()
            # Named by its path below that folder, or (host/'s libraries) by its name in its folder's list.
            in_parent = os.path.join(os.path.basename(folder), name)  # cortex-m/runtime.cpp
            if os.path.relpath(path, lists) not in text and name not in text and in_parent not in everything:
                missing.append(f"{rel}: not in {os.path.relpath(os.path.join(lists, 'CMakeLists.txt'), root)}")
    for m in missing:
        print(m)
    if missing:
        print(f"check-sources: {len(missing)} file(s) not built", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
