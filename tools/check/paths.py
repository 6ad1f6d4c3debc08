#!/usr/bin/env python3
"""Every repository path named in a comment or a doc exists.

Reads the tracked source, script and documentation files (git ls-files), picks out the words that name a
file or folder of this repository — a word starting with one of its top-level folders (host/player/x.cpp,
docs/view.md, host/player/player.*), or a Markdown link to a local file — and checks each against the
tree. Build outputs (build/…, generated names) and things outside the repository (/dev/…, URLs) are not
paths of the tree and are left alone. Prints one line per missing path (FILE:LINE: PATH) and exits 1 when
there is any, 0 otherwise.

usage: tools/check/paths.py [REPO]
"""
import glob
import os
import re
import subprocess
import sys

TOP = ("boards", "cmake", "docs", "examples", "firmware", "host", "scripts", "shared", "tests", "tools", ".ci")
TEXT = (".cpp", ".hpp", ".h", ".c", ".cmake", ".txt", ".md", ".sh", ".bash", ".py", ".in", ".ld", ".json", ".toml")
# A word that starts at a top-level folder: letters, digits and ._-/ then an optional * pattern.
WORD = re.compile(r"(?<![\w/.<>$-])((?:%s)/[\w./*+-]*[\w*])" % "|".join(re.escape(t) for t in TOP))
MD_LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def comment_text(path, line):
    """The part of a line that is prose: a C++ comment, a #-comment of a script or CMake file, a whole
    line of a doc."""
    if path.endswith((".cpp", ".hpp", ".h", ".c", ".ld")):
        starts = [i for i in (line.find("//"), line.find("/*")) if i >= 0]
        if starts:
            return line[min(starts):]
        return line if line.lstrip().startswith("*") else ""
    if path.endswith(".md"):
        return line
    at = re.search(r"(?:^|\s)#", line)  # not the # inside a word or a link's anchor
    return line[at.start():] if at else ""


def exists(root, word):
    """A path, a glob (host/player/player.*), a stem naming its files (shared/spidar/pose for pose.hpp and
    pose.cpp), or a pair written X.hpp/.cpp."""
    word = word.rstrip(".")
    if "/." in word:  # firmware/drive.hpp/.cpp
        first, _, ext = word.rpartition("/.")
        stem = os.path.splitext(first)[0]
        return exists(root, first) and exists(root, stem + "." + ext)
    full = os.path.join(root, word)
    if any(c in word for c in "*?["):
        return bool(glob.glob(full))
    return os.path.exists(full) or bool(glob.glob(full + ".*"))


def placeholder(word):
    """host/FOLDER/*.cpp, tools/bench/NAME.sh: a pattern for the reader, not a path."""
    return any(re.fullmatch(r"[A-Z_]{3,}", part) for part in re.split(r"[/.-]", word))


def tracked_files(root):
    """git ls-files; a tree that is not a git checkout (an unpacked archive): every file but build/."""
    try:
        return subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        out = []
        for folder, dirs, names in os.walk(root):
            dirs[:] = [d for d in dirs if d not in (".git", "build")]
            out += [os.path.relpath(os.path.join(folder, n), root) for n in names]
        return out


def main(argv):
    root = os.path.abspath(argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
    files = tracked_files(root)
    missing = []
    for rel in files:
        if not rel.endswith(TEXT) and not rel.startswith("scripts/"):
            continue
        if rel.startswith("tests/data/") or rel.startswith("fuzz-artifacts/"):
            continue
        try:
            with open(os.path.join(root, rel), encoding="utf-8") as f:
                lines = f.read().splitlines()
        except (UnicodeDecodeError, IsADirectoryError):
            continue
        for number, line in enumerate(lines, 1):
            text = comment_text(rel, line)
            for match in WORD.finditer(text):
                word = match.group(1)
                if text[match.end():].startswith(("…", "-…")):  # examples/bach-bwv1050-…: a name's start
                    word += "*"
                if not placeholder(word) and not exists(root, word):
                    missing.append(f"{rel}:{number}: {word}")
            if rel.endswith(".md"):
                for target in MD_LINK.findall(text):
                    if re.match(r"^[a-z]+:", target) or target.startswith("/"):
                        continue  # a URL or an absolute path
                    if not os.path.exists(os.path.join(root, os.path.dirname(rel), target)):
                        missing.append(f"{rel}:{number}: {target}")
    for m in missing:
        print(m)
    if missing:
        print(f"check-paths: {len(missing)} path(s) named but not in the tree", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
