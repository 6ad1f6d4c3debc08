#!/usr/bin/env bash
# The manual pages and the bash completion the build writes (<build>/share/, host/cli/manual.hpp) against
# the program's own --help (CLI11's formatter, not ours): every command has a page, each page lists
# exactly the options `hmp COMMAND --help` lists, man renders it without a warning, and completing
# `hmp COMMAND --` offers exactly those options.
# Usage: manual.sh HMP REPO (HMP in <build>/bin/).
hmp="$1"
source "$(dirname "$0")/lib.bash"
build=$(cd "$(dirname "$hmp")/.." && pwd)
man1="$build/share/man/man1" completion="$build/share/bash-completion/completions/hmp"
[ -f "$completion" ] || { echo "FAIL: no $completion"; exit 1; }

# The commands, from the top-level help's "Subcommands:" list.
mapfile -t commands < <("$hmp" --help | sed -n '/^Subcommands:/,$p' | awk 'NR > 1 && NF {print $1}')
[ ${#commands[@]} -ge 10 ] || { echo "FAIL: only ${#commands[@]} commands in hmp --help"; exit 1; }
render() { MANWIDTH=200 LC_ALL=C.UTF-8 man --warnings -l "$1" 2>"$tmp/warnings" | col -b; }
render "$man1/hmp.1.gz" >"$tmp/hmp.txt"
[ -s "$tmp/warnings" ] && { echo "FAIL: man warns on hmp.1: $(<"$tmp/warnings")"; fail=1; }
long_options() { grep -o -- '--[a-z][a-z0-9-]*' | sort -u; }
for c in "${commands[@]}"; do
  page="$man1/hmp-$c.1.gz"
  [ -f "$page" ] || { echo "FAIL: no page for $c"; fail=1; continue; }
  grep -q "hmp-$c" "$tmp/hmp.txt" || { echo "FAIL: hmp(1) does not name hmp-$c"; fail=1; }
  render "$page" >"$tmp/page.txt"
  [ -s "$tmp/warnings" ] && { echo "FAIL: man warns on hmp-$c.1: $(<"$tmp/warnings")"; fail=1; }
  # The options of --help's "Options:" section, against those the page's OPTIONS section names.
  "$hmp" "$c" --help | sed -n '/^Options:/,/^[A-Z][a-z]*:$/p' | grep -E '^ +(-[a-z],)?--' | long_options >"$tmp/help"
  sed -n '/^OPTIONS/,/^[A-Z]/p' "$tmp/page.txt" | grep -E '^ {7}(-[a-z], )?--' | long_options >"$tmp/man"
  if ! cmp -s "$tmp/help" "$tmp/man"; then
    echo "FAIL: hmp-$c.1 options differ from hmp $c --help:"; diff "$tmp/help" "$tmp/man"; fail=1
  fi
  offered=$(bash -c 'source "$1"; COMP_WORDS=(hmp "$2" --); COMP_CWORD=2; _hmp; printf "%s\n" "${COMPREPLY[@]}"' \
            _ "$completion" "$c" | long_options)
  check "completion of hmp $c --" "$(<"$tmp/help")" "$offered"
done
# A command's name completes, and the value of an option that takes a file completes to files.
check "completion of hmp pl" play \
  "$(bash -c 'source "$1"; COMP_WORDS=(hmp pl); COMP_CWORD=1; _hmp; echo "${COMPREPLY[@]}"' _ "$completion")"
touch "$tmp/song.mid"
check "completion of hmp play --soundfont <file>" "$tmp/song.mid" \
  "$(bash -c 'source "$1"; COMP_WORDS=(hmp play --soundfont "$2"); COMP_CWORD=3; _hmp; echo "${COMPREPLY[@]}"' \
     _ "$completion" "$tmp/so")"
exit $fail
