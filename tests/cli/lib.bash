# The command-line tests' shared part (tests/cli/*.sh source it after setting $hmp, the program):
# a scratch directory $tmp removed at the end, $fail set by any failed check, and the checks.
# (Not a test itself: CTest runs the *.sh files.)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0

run_env=()     # words before "$hmp" in run (e.g. env -u DISPLAY: no display)
bad_prefix=()  # words before the arguments in expect_bad (e.g. the subcommand and its song)

# check WHAT EXPECTED ACTUAL
check() {
  if [ "$2" != "$3" ]; then echo "FAIL: $1: expected [$2], got [$3]"; fail=1; fi
}

# run ARGS...: hmp's stdout, stderr and exit code into $out, $err and $rc
run() {
  "${run_env[@]}" "$hmp" "$@" >"$tmp/out" 2>"$tmp/err"; rc=$?
  out=$(<"$tmp/out"); err=$(<"$tmp/err")
}

# expect_ok ARGS...: hmp accepts ARGS (exit 0); its output in $tmp/out and $tmp/err
expect_ok() {
  "$hmp" "$@" >"$tmp/out" 2>"$tmp/err" || { echo "FAIL: hmp $* -> rc=$?"; cat -v "$tmp/err"; fail=1; }
}

# expect_bad WORD ARGS...: hmp refuses ARGS with exit 2 and one stderr line containing WORD (any case)
expect_bad() {
  local word="$1"; shift
  "$hmp" "${bad_prefix[@]}" "$@" >"$tmp/out" 2>"$tmp/err" </dev/null; local rc=$?
  local lines; lines=$(wc -l <"$tmp/err")
  if [ $rc -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -qi -- "$word" "$tmp/err"; then
    echo "FAIL: hmp ${bad_prefix[*]} $* -> rc=$rc, $lines stderr line(s), wanted '$word':"; cat "$tmp/err"; fail=1
  fi
}
