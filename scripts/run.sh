#!/usr/bin/env bash
# Fresh machine to editor in one command: installs what is missing, builds, and opens the SoftTouch
# editor on the bundled default scene (the angelfish swim). Extra arguments go to the editor
# (e.g. a project path). Without a display it says so and writes a screenshot instead.
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what the editor needs, and only the editor (with its device plugins): no test suites, fuzzers or benchmarks.
bash scripts/install-deps.sh --editor
bash scripts/build.sh release softtouch
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec ./build/bin/softtouch "$@"
fi
mkdir -p out
echo "No display found (DISPLAY is unset): rendering the editor under Xvfb to out/editor.png instead."
xvfb-run -a -s "-screen 0 1600x1000x24" ./build/bin/softtouch --screenshot out/editor.png --seconds 1 "$@"
echo "Wrote out/editor.png. On a desktop, run: ./build/bin/softtouch [PROJECT]"
