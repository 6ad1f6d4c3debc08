#!/usr/bin/env bash
# tools/check/paths.py: every repository path named in a comment or a doc exists. It passes on this tree,
# and on a small tree built here it finds exactly the paths that are missing (and nothing else: globs,
# stems, X.hpp/.cpp pairs, placeholders, URLs and code outside comments are not reported).
set -u
hmp="$1"; repo="$2"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
check_paths="$repo/tools/check/paths.py"

out=$(python3 "$check_paths" "$repo" 2>&1); rc=$?
check "the repository's paths" 0 "$rc"
[ $rc -eq 0 ] || echo "$out"

t="$tmp/tree"
mkdir -p "$t/host/player" "$t/docs" "$t/tools"
touch "$t/host/player/player.hpp" "$t/host/player/player.cpp" "$t/docs/view.md"
cat >"$t/host/player/player.cpp" <<'CPP'
// See host/player/player.hpp, host/player/player.*, host/player/player (its files), host/player/player.hpp/.cpp,
// docs/view.md, host/FOLDER/*.cpp, https://example.org/host/x.cpp and /dev/hidraw0.
// Gone: host/player/gone.cpp and docs/gone.md.
const char* s = "host/player/not_a_comment.cpp";
CPP
cat >"$t/docs/index.md" <<'MD'
[the view](view.md) · [missing](missing.md#anchor) · [web](https://example.org/x.md) · tools/nothing.py
MD
(cd "$t" && git init -q && git add -A) 2>/dev/null || true
out=$(python3 "$check_paths" "$t" 2>/dev/null); rc=$?
check "a tree with missing paths: exit" 1 "$rc"
check "a tree with missing paths: what it names" \
  "docs/index.md:1: missing.md
docs/index.md:1: tools/nothing.py
host/player/player.cpp:3: docs/gone.md
host/player/player.cpp:3: host/player/gone.cpp" "$(LC_ALL=C sort <<<"$out")"
exit $fail
