#!/usr/bin/env python3
"""The C++ sources are as clang-format leaves them (.clang-format at the root) and no line is longer than
the column limit (clang-format cannot break a long string literal). Prints one line per file or line that
is off and exits 1 when there is any; 2 when clang-format is missing.

usage: tools/check/format.py [REPO]
Checks the files git tracks (every .cpp/.hpp/.h/.c file outside build/ where REPO is not a clone).
Fix with: clang-format -i FILE...
"""
import os
import re
import shutil
import subprocess
import sys

EXTENSIONS = (".cpp", ".hpp", ".h", ".c")
SKIP = ("build", ".git")


def column_limit(root):
    with open(os.path.join(root, ".clang-format")) as f:
        m = re.search(r"^ColumnLimit:\s*(\d+)", f.read(), re.M)
    return int(m.group(1)) if m else 80


def sources(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout
        files = out.split()
    except (OSError, subprocess.CalledProcessError):
        files = []
    if not files:  # not a clone: the files on disk
        for folder, dirs, names in os.walk(root):
            dirs[:] = sorted(d for d in dirs if d not in SKIP and not d.startswith("."))
            files += [os.path.relpath(os.path.join(folder, n), root) for n in sorted(names)]
    return [f for f in files if f.endswith(EXTENSIONS) and os.path.exists(os.path.join(root, f))]


def main(argv):
    root = os.path.abspath(argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
    tool = shutil.which("clang-format")
    if tool is None:
        print("check-format: clang-format is not installed (scripts/setup installs it)", file=sys.stderr)
        return 2
    files = sources(root)
    limit = column_limit(root)
    bad = []
    # --dry-run --Werror names each file that would change; in batches so the command line stays short.
    for i in range(0, len(files), 100):
        r = subprocess.run([tool, "--dry-run", "--Werror", "--style=file", *files[i:i + 100]], cwd=root,
                           capture_output=True, text=True)
        named = sorted({line.split(":")[0] for line in r.stderr.splitlines() if ": error:" in line})
        bad += [f"{f}: not formatted (clang-format -i {f})" for f in named]
        if r.returncode != 0 and not named:
            print(f"check-format: clang-format failed: {r.stderr.strip()}", file=sys.stderr)
            return 2
    for f in files:
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as text:
            for n, line in enumerate(text.read().split("\n"), 1):
                if len(line) > limit:
                    bad.append(f"{f}:{n}: {len(line)} columns, over {limit}")
    for b in bad:
        print(b)
    if bad:
        print(f"check-format: {len(bad)} problem(s) in {len(files)} files", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
