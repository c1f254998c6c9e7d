#!/bin/sh
# Runs the sanitizer build of volillum-render (the path in VOLILLUM_SANITIZED_CLI) with
# Mesa's software GL driver kept loaded: the driver leaks a little at exit and is unloaded
# before LeakSanitizer reports, which would leave its leaks without a module name that
# lsan.supp could suppress. Used by ./setup.sh sanitize for the fuzz corpus.
driver=$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -n 1)
exec env LD_PRELOAD="$driver" \
  ASAN_OPTIONS="detect_leaks=1:verify_asan_link_order=0:abort_on_error=0" \
  LSAN_OPTIONS="suppressions=$(dirname "$0")/lsan.supp" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
  "$VOLILLUM_SANITIZED_CLI" "$@"
