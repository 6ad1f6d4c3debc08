#!/usr/bin/env bash
# tools/check/format.py: the C++ sources are as clang-format leaves them and within the column limit. It
# passes on this tree; on a small tree built here it names exactly the file clang-format would change and
# the line that is too long, and nothing that is well formatted.
set -u
hmp="$1"; repo="$2"
source "$(dirname "${BASH_SOURCE[0]}")/lib.bash"
check_format="$repo/tools/check/format.py"

out=$(python3 "$check_format" "$repo" 2>&1); rc=$?
check "the repository's sources" 0 "$rc"
[ $rc -eq 0 ] || echo "$out"

t="$tmp/tree"
mkdir -p "$t/host"
cp "$repo/.clang-format" "$t/"
printf 'int add(int a, int b) { return a + b; }\n' >"$t/host/good.cpp"
printf 'int   add(int a,int b){return a+b;}\n' >"$t/host/messy.cpp"
printf '// https://example.org/%s\n' "$(printf 'x%.0s' $(seq 1 110))" >"$t/host/long.hpp"  # no place to break
out=$(python3 "$check_format" "$t" 2>/dev/null); rc=$?
check "a tree with a messy file and a long line: exit" 1 "$rc"
check "a tree with a messy file and a long line: what it names" \
  "host/long.hpp:1: 133 columns, over 120
host/messy.cpp: not formatted (clang-format -i host/messy.cpp)" "$(LC_ALL=C sort <<<"$out")"
exit $fail
