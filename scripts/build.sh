#!/usr/bin/env bash
# Configures and builds one CMake preset (default: release), or only the named targets.
# Usage: scripts/build.sh [release|debug|asan] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
cmake --preset "$preset" >/dev/null
targets=()
[ $# -eq 0 ] || targets=(--target "$@")
cmake --build --preset "$preset" -j "$(nproc)" "${targets[@]}"
