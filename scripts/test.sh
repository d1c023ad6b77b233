#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs every test through ctest.
# --with-asan also builds and runs the whole suite under AddressSanitizer + UndefinedBehaviorSanitizer; that
# build starts with the release build, in the background at the lowest priority, so it uses the cores the
# release build and suite leave idle (scripts/step.sh).
# Each step's wall time goes to stderr (scripts/step.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/step.sh
trap stop_background EXIT
with_asan=false
[ "${1:-}" = "--with-asan" ] && with_asan=true
step "install" bash scripts/install-deps.sh
$with_asan && background "sanitizer build (the part left after the release suite)" bash scripts/build.sh asan
step "release build" bash scripts/build.sh release
step "release suite" ctest --preset release -j "$(nproc)"
if $with_asan; then
  finish "sanitizer build (the part left after the release suite)"
  # intercept_tls_get_addr=0: LeakSanitizer's thread scan (GCC 12's libasan) crashes now and then ("Tracer
  # caught signal 11") walking the dynamic TLS of Mesa's dlopen'ed driver in a headless render; a batch of
  # two renders at once failed 4 runs in 6 with it on, none in 4 with it off (docs/design/reliability.md).
  ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1 \
    step "sanitizer suite" ctest --preset asan -j "$(nproc)"
fi
