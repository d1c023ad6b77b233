#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs every test through ctest.
# --with-asan also builds (clang) and runs the whole suite under AddressSanitizer + UndefinedBehaviorSanitizer;
# that build makes the libFuzzer targets too (scripts/fuzz.sh).
# What only the suites need (Chromium, Blender, Slurm, ...) is downloaded and installed while the release
# build compiles: on a fresh machine the download waits on the network, not on the cores.
# Each step's wall time goes to stderr (scripts/step.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
. scripts/step.sh
trap stop_background EXIT
step "install, to build" bash scripts/install-deps.sh --build
background "install, to test (what was left after the release build)" bash scripts/install-deps.sh --test
step "release build" bash scripts/build.sh release
finish "install, to test (what was left after the release build)"
step "release suite" ctest --preset release -j "$(nproc)"
if [ "${1:-}" = "--with-asan" ]; then
  step "sanitizer build" bash scripts/build.sh asan
  # intercept_tls_get_addr=0: LeakSanitizer's thread scan (seen with GCC 12's libasan) crashes now and then ("Tracer
  # caught signal 11") walking the dynamic TLS of Mesa's dlopen'ed driver in a headless render; a batch of
  # two renders at once failed 4 runs in 6 with it on, none in 4 with it off (docs/design/reliability.md).
  ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1 \
    step "sanitizer suite" ctest --preset asan -j "$(nproc)"
fi
