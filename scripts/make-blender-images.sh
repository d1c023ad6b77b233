#!/usr/bin/env bash
# Makes the pictures of docs/blender.md in Blender itself (Debian's 3.4, scripts/install-deps.sh --test installs it),
# with the add-on from blender/addons and the built softtouch-cli (run scripts/build.sh first): the scene is made
# headless, then Blender's window is opened under Xvfb and driven by simulated mouse events, as a user would.
set -euo pipefail
cd "$(dirname "$0")/.."
out="$PWD/docs/images"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
export BLENDER_USER_SCRIPTS="$PWD/blender" SOFTTOUCH_CLI="$PWD/build/bin/softtouch-cli" HOME="$tmp"
blender -b --factory-startup --python scripts/blender-images.py -- scene "$tmp/guppy.blend" >"$tmp/scene.log" 2>&1 ||
  { cat "$tmp/scene.log"; exit 1; }
xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --enable-event-simulate "$tmp/guppy.blend" \
  --python scripts/blender-images.py -- pictures "$out" >"$tmp/ui.log" 2>&1 || { cat "$tmp/ui.log"; exit 1; }
grep -q "pictures done" "$tmp/ui.log" || { cat "$tmp/ui.log"; exit 1; }
ls -l "$out"/blender-*.png
