#!/usr/bin/env bash
# Fails if a firmware image contains heap or exception machinery (design §8: no allocation; developer
# guide: no exceptions). Looks at every symbol nm reports, defined or not.
# Usage: check_no_heap_symbols.sh NM IMAGE.elf...
set -euo pipefail
nm_tool=${1:?usage: check_no_heap_symbols.sh NM IMAGE.elf...}
shift
[ $# -gt 0 ] || { echo "no images given" >&2; exit 2; }

# Mangled names: operator new/delete are _Znw*/_Zna*/_Zdl*/_Zda*; _malloc_r etc. are newlib's reentrant
# allocator entry points; __aeabi_unwind_cpp_pr* are the EHABI personality routines that drag in the unwinder.
forbidden='^(malloc|free|calloc|realloc|reallocf|reallocarray|memalign|valloc|pvalloc|aligned_alloc|posix_memalign'
forbidden+='|_malloc_r|_free_r|_calloc_r|_realloc_r|_memalign_r|__malloc_lock|_sbrk|_sbrk_r|sbrk'
forbidden+='|_Znw.*|_Zna.*|_Zdl.*|_Zda.*'
forbidden+='|__cxa_throw|__cxa_rethrow|__cxa_allocate_exception|__cxa_begin_catch|__cxa_end_catch'
forbidden+='|__gxx_personality_v0|__aeabi_unwind_cpp_pr[0-9]|_Unwind_.*)$'

status=0
for image in "$@"; do
  symbols=$("$nm_tool" "$image" | awk '{print $NF}')
  count=$(printf '%s\n' "$symbols" | grep -c . || true)
  if [ "$count" -eq 0 ]; then
    echo "FAIL $image: nm listed no symbols (stripped image?)"
    status=1
    continue
  fi
  bad=$(printf '%s\n' "$symbols" | grep -E "$forbidden" | sort -u || true)
  if [ -n "$bad" ]; then
    echo "FAIL $image: forbidden symbols present:"
    printf '%s\n' "$bad" | while read -r s; do printf '  %s  (%s)\n' "$s" "$("${nm_tool%nm}c++filt" "$s" 2>/dev/null || echo "$s")"; done
    status=1
  else
    echo "OK   $image: $count symbols, no heap/exception symbols"
  fi
done
exit $status
