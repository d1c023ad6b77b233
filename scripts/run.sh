#!/usr/bin/env bash
# Fresh machine to result in one command: installs what is missing, builds, and bakes the bundled
# default scene (the angelfish swim) headless into out/, saying where the files went.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh release
mkdir -p out
./build/bin/softtouch-cli bake presets/scenes/angelfish-swim.softtouch --out out/angelfish-swim.pc2
echo "Import out/angelfish-swim.obj into your DCC tool and attach out/angelfish-swim.pc2 as a point cache."
